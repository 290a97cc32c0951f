//! What a frame leaves for the host: the culling counters, the timestamps of each pass
//! and the triangles the grass draw generated, each in per-slot objects the renderer
//! writes and the frame driver reads once the slot's fence has signalled.

use crate::answers::Answers;
pub use crate::passes::Mark;
use crate::vulkan::query::{TimestampPool, TrianglePool};
use crate::vulkan::{Buffer, Context};
use anyhow::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::Blade;
use shared::gpu::counters;
use shared::gpu::counters::COUNTER_COUNT;
use shared::query::{QUERY_WORDS, Question, Tally};
use shared::sim::cut::{CUT_SLOTS, CUT_WORDS, as_cut};
use std::sync::Arc;

/// How the compute pass sorted the blades of one frame: drawn, or removed by the
/// first test that failed. Every blade lands in exactly one count.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct CullCounts {
    /// Drawn.
    pub drawn: u32,
    /// Removed by the orientation test.
    pub orientation: u32,
    /// Removed by the frustum test.
    pub frustum: u32,
    /// Removed by the distance test.
    pub distance: u32,
    /// Removed by the occlusion test.
    pub occlusion: u32,
    /// Blades the pass looked at, counted on the GPU: each adds to one outcome's
    /// count (drawn, removed by a test, or far), and their sum is the field's size.
    pub examined: u32,
    /// Visible blades drawn by the compute rasterizer (not in `drawn`).
    pub compute: u32,
    /// Of the mesh path's, the blades their bucket's part of the binned list had no
    /// room for (`meshlet::BinLayout`), drawn at the most segments.
    pub spilled: u32,
    /// Pixels the compute rasterizer's blades covered on the target.
    pub raster_covered: u32,
    /// Of those, the pixels it wrote (in front of the hardware's depth and of the far
    /// blade the pixel held).
    pub raster_written: u32,
    /// A tiled field's far tiles in view.
    pub far_tiles: u32,
    /// The far blades they asked for (generated up to the field's room).
    pub far_blades: u32,
    /// Far tiles that found too little room.
    pub tiles_short: u32,
    /// Tiles in the view volume the occlusion test hid at tile level.
    pub tiles_hidden: u32,
    /// Blades drawn into the sun's shadow map (the natural look with shadows): every
    /// cascade's casters.
    pub casters: u32,
    /// Of those, the ones drawn into the near cascade too.
    pub near_casters: u32,
    /// Blades within reach of a collider, handed to the collision pass.
    pub collided: u32,
    /// Blades a cutter cut (`shared::sim::cut`).
    pub cut: u32,
    /// Cuts the cut table had no room for.
    pub cuts_dropped: u32,
}

impl CullCounts {
    fn from_counters(c: &[u32]) -> Self {
        Self {
            drawn: c[counters::COUNTER_VISIBLE],
            orientation: c[counters::COUNTER_ORIENTATION],
            frustum: c[counters::COUNTER_FRUSTUM],
            distance: c[counters::COUNTER_DISTANCE],
            occlusion: c[counters::COUNTER_OCCLUSION],
            examined: counters::examined(c),
            compute: c[counters::COUNTER_FAR],
            spilled: c[counters::COUNTER_SPILLED],
            raster_covered: c[counters::COUNTER_RASTER_COVERED],
            raster_written: c[counters::COUNTER_RASTER_WRITTEN],
            far_tiles: c[counters::COUNTER_TILES],
            far_blades: c[counters::COUNTER_TILE_BLADES],
            tiles_short: c[counters::COUNTER_TILES_SHORT],
            tiles_hidden: c[counters::COUNTER_TILES_HIDDEN],
            casters: c[counters::COUNTER_CASTERS],
            near_casters: c[counters::COUNTER_NEAR_CASTERS],
            collided: c[counters::COUNTER_NEAR],
            cut: c[counters::COUNTER_CUTS],
            cuts_dropped: c[counters::COUNTER_CUTS_DROPPED],
        }
    }
    /// Blades removed by any test.
    pub fn removed(&self) -> u32 {
        self.orientation + self.frustum + self.distance + self.occlusion
    }
    /// (test name, blades it removed), in the order the tests run.
    pub fn by_test(&self) -> [(&'static str, u32); 4] {
        let removed = [
            self.orientation,
            self.frustum,
            self.distance,
            self.occlusion,
        ];
        std::array::from_fn(|i| (shared::cull::blade::TEST_NAMES[i], removed[i]))
    }
}

/// GPU time of each pass of one frame, in milliseconds, from timestamp queries.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// Uniform update and counter reset, then the occluder depth pre-pass and the
    /// pyramid reduction (when they run).
    pub depth_pyramid: f64,
    /// Simulate, cull, compact and write the draws.
    pub simulate_cull: f64,
    /// The sun's shadow map.
    pub shadow: f64,
    /// Ground and ball.
    pub ground: f64,
    /// Grass.
    pub grass: f64,
    /// The compute rasterizer: the hardware's depth copied, the visibility buffer
    /// cleared, the far blades drawn.
    pub raster: f64,
    /// The compute rasterizer's resolve and the multisample resolve.
    pub resolve: f64,
    /// The natural look's shading after the draw (one sample per pixel).
    pub shade: f64,
    /// Temporal resolve, sky and tone map.
    pub tone_map: f64,
    /// Overlay.
    pub overlay: f64,
    /// The whole frame on the GPU.
    pub total: f64,
}

impl PassTimes {
    /// Each pass's time with its name, in the frame's order (the total apart).
    pub fn named(&self) -> [(&'static str, f64); 10] {
        [
            ("uploads + depth pyramid", self.depth_pyramid),
            ("simulate + cull", self.simulate_cull),
            ("shadow map", self.shadow),
            ("ground", self.ground),
            ("grass", self.grass),
            ("compute raster", self.raster),
            ("far resolve + MSAA resolve", self.resolve),
            ("shading (natural)", self.shade),
            ("TAA + sky + tone map", self.tone_map),
            ("overlay", self.overlay),
        ]
    }

    /// The pass that took longest, with its time.
    pub fn longest(&self) -> (&'static str, f64) {
        self.named().into_iter().fold(
            ("", f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        )
    }

    /// From the milliseconds since [`Mark::Start`] at each later mark.
    fn from_marks(m: &[f64]) -> Self {
        let at = |mark: Mark| m[mark as usize - 1];
        Self {
            depth_pyramid: at(Mark::Pyramid),
            simulate_cull: at(Mark::SimulateCull) - at(Mark::Pyramid),
            shadow: at(Mark::Shadow) - at(Mark::SimulateCull),
            grass: at(Mark::Grass) - at(Mark::Shadow),
            ground: at(Mark::Ground) - at(Mark::Grass),
            raster: at(Mark::Raster) - at(Mark::Ground),
            resolve: at(Mark::Resolve) - at(Mark::Raster),
            shade: at(Mark::Shade) - at(Mark::Resolve),
            tone_map: at(Mark::ToneMap) - at(Mark::Shade),
            overlay: at(Mark::Overlay) - at(Mark::ToneMap),
            total: at(Mark::Overlay),
        }
    }
}

/// What the newest frame read back left: its counts, pass times, triangles and
/// answers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Readback {
    /// The culling tests' counts.
    pub counts: Option<CullCounts>,
    /// GPU time per pass, where the device has timestamps.
    pub times: Option<PassTimes>,
    /// Triangles the grass draw generated (pipeline statistics, where the device has
    /// them).
    pub triangles: Option<u64>,
    /// Its answers to the questions asked of the grass, and its contacts.
    pub answers: Answers,
}

impl Readback {
    /// Visible (drawn) blades.
    pub fn visible(&self) -> Option<u32> {
        self.counts.map(|c| c.drawn)
    }
}

/// One frame slot's queries and the host copy of its counters and answers.
pub struct FrameQueries {
    /// The counters, copied at the end of the compute pass.
    pub counters: Buffer,
    /// The query buffer (`shared::query::QUERY_WORDS`), copied with the counters.
    pub answers: Buffer,
    /// One timestamp per [`Mark`], where the device has them.
    pub timestamps: Option<TimestampPool>,
    /// The grass draw's triangles, where the device counts them.
    pub triangles: Option<TrianglePool>,
}

impl FrameQueries {
    /// The objects of one slot.
    pub fn new(ctx: &Arc<Context>) -> Result<Self> {
        Ok(Self {
            counters: Buffer::new(
                ctx,
                "counter readback",
                counters::COUNTER_BYTES,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            answers: Buffer::new(
                ctx,
                "answer readback",
                (QUERY_WORDS * 4) as u64,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            timestamps: TimestampPool::new(ctx, Mark::COUNT)?,
            triangles: TrianglePool::new(ctx)?,
        })
    }

    /// What the slot's last frame left (call once its fence has signalled).
    pub fn read(&self) -> Result<Readback> {
        let counters = self.counters.read::<u32>(COUNTER_COUNT)?;
        Ok(Readback {
            counts: Some(CullCounts::from_counters(&counters)),
            times: self
                .timestamps
                .as_ref()
                .and_then(TimestampPool::read_ms)
                .map(|m| PassTimes::from_marks(&m)),
            triangles: self.triangles.as_ref().and_then(TrianglePool::read),
            answers: Answers::from_words(&self.answers.read::<u32>(QUERY_WORDS)?),
        })
    }
}

impl super::Renderer {
    /// Copies a device buffer into host memory and returns `count` values of `T`.
    pub fn download<T: bytemuck::Pod>(&self, buffer: &Buffer, count: usize) -> Result<Vec<T>> {
        let bytes = (count * size_of::<T>()) as u64;
        let staging = Buffer::new(
            &self.ctx,
            "download",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.ctx.wait_idle()?;
        self.pool
            .one_shot(|rec| rec.copy_buffer(buffer.buffer, staging.buffer, bytes))?;
        staging.read(count)
    }

    /// The answers to `questions` over the field's simulated blades as the newest
    /// frame left them, on the host (`shared::query`): the blades and the cut table
    /// read back (waiting for the device), each blade as the cut table leaves it at the
    /// frame's time, as the query pass reads it.
    pub fn host_answers(&self, questions: &[Question]) -> Result<Vec<Tally>> {
        let count = self.field.simulated as usize;
        let mut blades: Vec<Blade> = self.download(&self.field.blades, count)?;
        let forces = &self.block().forces;
        if forces.cutting != 0 {
            let words = CUT_SLOTS as usize * CUT_WORDS;
            let cuts: Vec<u32> = self.download(&self.field.cuts, words)?;
            for b in &mut blades {
                *b = as_cut(b, &cuts, forces.time, forces.regrow);
            }
        }
        Ok(questions.iter().map(|q| q.tally(&blades)).collect())
    }
}
