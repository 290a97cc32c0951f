//! One frame, start to end: update the uniforms and reset the counters (transfer);
//! draw the occluders' depth and reduce it to a pyramid (graphics, compute); simulate,
//! cull and count (compute); draw ground and grass, then the overlay (graphics). The
//! renderer records a frame; the frame driver (`app::driver`) owns the slots,
//! submits and reads each slot's counters and timestamps back.

mod compute;
pub mod external;
#[cfg(feature = "test-hooks")]
mod hooks;
pub mod readback;
pub mod targets;
mod temporal;

pub use readback::{CullCounts, FrameQueries, Mark, PassTimes, Readback};

use crate::field::{Field, FieldBlades};
use crate::passes::draw::DrawPass;
use crate::passes::occlusion::OcclusionPass;
#[cfg(feature = "app")]
use crate::passes::overlay::{OverlayFrame, OverlayPass};
use crate::passes::shade::ShadePass;
use crate::passes::shadow::ShadowPass;
use crate::passes::simulate::SimulatePass;
use crate::passes::temporal::TemporalPass;
use crate::passes::tiles::TilesPass;
use crate::passes::tonemap::{ToneMapPass, ToneMapSource};
use crate::shaders;
use crate::tiles::TiledSpec;
use crate::vulkan::commands::CommandPool;
use crate::vulkan::pipeline::ShaderModules;
use crate::vulkan::{Context, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use compute::Asked;
use shared::Blade;
use shared::draw::shade::{MATERIAL_ROCK, MATERIAL_SOIL};
use shared::gpu::layout::{FrameUniforms, SimulatePush};
use shared::plan::{FieldPart, FrameFacts, FramePlan, FrameRequest};
use shared::settings::SHADOW_SIZES;
use shared::sim::collide::Collider;
use shared::world::mesh::SurfaceMesh;
use std::sync::Arc;
use targets::{DrawTargets, TargetSpec, draw_images, finish_frame, tone_map};
use temporal::Temporal;

#[cfg(feature = "app")]
use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// Every stage a frame's commands use: what one frame waits for before the next
/// overwrites its buffers (named stage by stage: the layer's best-practices check flags
/// `ALL_COMMANDS` and `ALL_GRAPHICS`).
pub(crate) const FRAME_STAGES: S = S::from_raw(
    S::COPY.as_raw()
        | S::CLEAR.as_raw()
        | S::COMPUTE_SHADER.as_raw()
        | S::DRAW_INDIRECT.as_raw()
        | S::VERTEX_ATTRIBUTE_INPUT.as_raw()
        | S::INDEX_INPUT.as_raw()
        | SHADER_STAGES.as_raw()
        | S::EARLY_FRAGMENT_TESTS.as_raw()
        | S::LATE_FRAGMENT_TESTS.as_raw()
        | S::COLOR_ATTACHMENT_OUTPUT.as_raw(),
);

/// Every shader stage a frame runs.
const SHADER_STAGES: S = S::from_raw(
    S::COMPUTE_SHADER.as_raw()
        // Vertex, tessellation and, where the device has them, mesh.
        | S::PRE_RASTERIZATION_SHADERS.as_raw()
        | S::FRAGMENT_SHADER.as_raw(),
);

/// Sky colour behind the field (linear).
pub(crate) const SKY: [f32; 4] = [0.42, 0.62, 0.86, 1.0];

/// What a frame renders into.
#[derive(Copy, Clone)]
pub struct Target {
    /// The colour image.
    pub image: vk::Image,
    /// Its view.
    pub view: vk::ImageView,
    /// Its size.
    pub extent: vk::Extent2D,
    /// Layout it must be left in (present, transfer source for a capture, or general
    /// for a host-linear image the host reads).
    pub final_layout: vk::ImageLayout,
    /// The image takes transfer writes: the overlay copies its opaque part into it
    /// (false: it blends all it covers).
    pub transfer_dst: bool,
}

/// What one frame asks of the renderer.
pub struct FrameInput<'a> {
    /// Where it renders.
    pub target: Target,
    /// What the frame shows: the renderer plans it and builds its block from it.
    pub request: FrameRequest,
    /// The simulation steps to run.
    pub push: SimulatePush,
    /// Receives the rendered pixels (target left in TRANSFER_SRC_OPTIMAL).
    pub capture: Option<vk::Buffer>,
    /// The overlay to draw over the frame, if any.
    #[cfg(feature = "app")]
    pub overlay: Option<OverlayFrame<'a>>,
    /// Without the program (the `app` feature) there is no overlay: always `None`.
    #[cfg(not(feature = "app"))]
    pub overlay: Option<std::marker::PhantomData<&'a ()>>,
}

/// What the renderer draws: the blades and the surfaces under them.
pub struct Meshes<'a> {
    /// The blades at rest.
    pub blades: &'a [Blade],
    /// The ground grass grows on (drawn as soil).
    pub surface: &'a SurfaceMesh,
    /// Surfaces without grass (drawn as rock).
    pub bare: &'a SurfaceMesh,
    /// The collider ball: a unit sphere, placed and sized per frame.
    pub ball: &'a SurfaceMesh,
    /// Some surface can hide grass (else the occlusion pre-pass is skipped).
    pub has_occluders: bool,
    /// A tiled field's layout: then `blades` is empty and the blades come from tiles.
    pub tiles: Option<TiledSpec>,
    /// The painted maps (`shared::paint` words; empty for none).
    pub paint: &'a [u32],
    /// A stored field's map square: its centre (x, z) and half its side
    /// (`Scene::paint_square`); a tiled field's is its layout's.
    pub paint_square: (glam::Vec2, f32),
    /// The valley's half extent: its ground is drawn as a grid around the camera on
    /// its height field rather than from `surface` (`passes::ground`).
    pub valley: Option<f32>,
}

/// The renderer: the field and the passes of one frame.
pub struct Renderer {
    ctx: Arc<Context>,
    /// The field's buffers.
    pub field: Field,
    simulate: SimulatePass,
    draw: DrawPass,
    /// A tiled field's generation.
    pub tiles: Option<TilesPass>,
    /// Where a stored field reads its painted maps: the map square's centre and half
    /// side (a tiled field's layout has its own).
    stored_maps: shared::world::tiles::TileParams,
    occlusion: OcclusionPass,
    /// The scene has surfaces that can hide grass (else the pre-pass is skipped).
    pub has_occluders: bool,
    shadow: ShadowPass,
    tonemap: ToneMapPass,
    temporal_pass: TemporalPass,
    shade: ShadePass,
    #[cfg(feature = "app")]
    overlay: Option<OverlayPass>,
    color_format: vk::Format,
    /// Images of `color_format` take blits both ways: a frame drawn smaller is
    /// tone-mapped at its size and blitted up ([`TargetSpec::shown`]).
    blits_up: bool,
    targets: Option<DrawTargets>,
    /// (seed, clump size) the clump buffer was made for; `None` when it is stale.
    clumped: Option<(u32, f32)>,
    /// The newest frame's block.
    block: FrameUniforms,
    /// What the temporal anti-aliasing keeps from frame to frame.
    temporal: Temporal,
    /// Simulated time of the newest frame with a cutter (`FrameFacts::last_cut`).
    last_cut: f32,
    pool: CommandPool,
    module: ShaderModules,
}

impl Renderer {
    /// Uploads the blades and surfaces of `meshes` and builds every pipeline for a
    /// colour target of `color_format`.
    pub fn new(ctx: &Arc<Context>, meshes: &Meshes, color_format: vk::Format) -> Result<Self> {
        let pool = CommandPool::new(ctx)?;
        let source = match &meshes.tiles {
            Some(spec) => {
                spec.check()?;
                FieldBlades::Tiled {
                    paint: meshes.paint,
                    simulated: spec.pool_blades(),
                    far: spec.far_blades,
                    tile_words: spec.tile_words(),
                    ground: spec.ground,
                    species: shared::species::Mix {
                        weights: spec.params.species,
                    },
                }
            }
            None => FieldBlades::Stored {
                blades: meshes.blades,
                paint: meshes.paint,
            },
        };
        let field = Field::new(ctx, &pool, source)?;
        let module = ShaderModules::new(ctx, shaders::MODULES)?;
        let simulate = SimulatePass::new(ctx, &module, &field)?;
        let tiles = match meshes.tiles {
            Some(spec) => Some(TilesPass::new(ctx, &module, &field, spec)?),
            None => None,
        };
        let surfaces = [
            (meshes.surface, MATERIAL_SOIL),
            (meshes.bare, MATERIAL_ROCK),
        ];
        let draw = DrawPass::new(
            ctx,
            &pool,
            &module,
            &field,
            color_format,
            &surfaces,
            meshes.ball,
            meshes.valley,
        )?;
        let occlusion = OcclusionPass::new(ctx, &module, &field)?;
        // The smallest map until the first frame names its size.
        let shadow = ShadowPass::new(ctx, &pool, &module, &field, SHADOW_SIZES[0])?;
        let tonemap = ToneMapPass::new(ctx, &module, color_format)?;
        let temporal_pass = TemporalPass::new(ctx, &module)?;
        let shade = ShadePass::new(ctx, &module, &field)?;
        Ok(Self {
            ctx: ctx.clone(),
            field,
            simulate,
            draw,
            tiles,
            stored_maps: shared::world::tiles::TileParams {
                centre: meshes.paint_square.0,
                half_extent: meshes.paint_square.1,
                ..Default::default()
            },
            occlusion,
            has_occluders: meshes.has_occluders,
            shadow,
            tonemap,
            temporal_pass,
            shade,
            #[cfg(feature = "app")]
            overlay: None,
            color_format,
            blits_up: crate::vulkan::features::format_has(
                &ctx.instance,
                ctx.physical,
                color_format,
                vk::FormatFeatureFlags::BLIT_SRC | vk::FormatFeatureFlags::BLIT_DST,
            ),
            targets: None,
            clumped: None,
            block: bytemuck::Zeroable::zeroed(),
            temporal: Temporal::default(),
            last_cut: f32::NEG_INFINITY,
            pool,
            module,
        })
    }

    /// Builds the overlay pipeline for `slots` frames in flight: frames may then
    /// carry an [`OverlayFrame`].
    #[cfg(feature = "app")]
    pub fn enable_overlay(&mut self, slots: usize) -> Result<()> {
        if self.overlay.is_none() {
            let pass = OverlayPass::new(&self.ctx, &self.module, self.color_format, slots)?;
            self.overlay = Some(pass);
        }
        Ok(())
    }

    /// Replaces the field's blades by `blades` (as many), at rest.
    pub fn replace_blades(&mut self, blades: &[Blade]) -> Result<()> {
        self.ctx.wait_idle()?;
        self.clumped = None;
        self.last_cut = f32::NEG_INFINITY;
        self.field.replace_blades(&self.ctx, &self.pool, blades)
    }

    /// The device.
    // Used by the program (`app`).
    #[cfg_attr(not(feature = "app"), allow(dead_code))]
    pub(crate) fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// The shader modules the pipelines are made from.
    // Used by the program (`app`).
    #[cfg_attr(not(feature = "app"), allow(dead_code))]
    pub(crate) fn modules(&self) -> &ShaderModules {
        &self.module
    }

    /// The colour format of the frame's target.
    // Used by the program (`app`).
    #[cfg_attr(not(feature = "app"), allow(dead_code))]
    pub(crate) fn color_format(&self) -> vk::Format {
        self.color_format
    }

    /// Records `record` into a one-time command buffer and waits for it.
    // Used by the program (`app`).
    #[cfg_attr(not(feature = "app"), allow(dead_code))]
    pub(crate) fn one_shot(&self, record: impl FnOnce(&Recorder)) -> Result<()> {
        self.pool.one_shot(record)
    }

    /// Records one whole frame into `rec`: uniforms and counters, the depth pyramid,
    /// simulate and cull, ground, grass and overlay, the capture; its counters,
    /// timestamps and triangles go to `queries`, its overlay geometry to slot `slot`.
    #[cfg_attr(not(feature = "app"), allow(unused_variables))]
    pub fn record(
        &mut self,
        rec: &Recorder,
        queries: &FrameQueries,
        slot: usize,
        input: &FrameInput,
    ) -> Result<()> {
        let target = input.target;
        // Without anything to hide grass, the pyramid is neither built nor read.
        let plan = input
            .request
            .plan()
            .within(self.has_occluders, self.draw.raster.supported());
        let natural = plan.natural();
        // Drawn smaller than the target (a render scale under 1), into an image the
        // tone map scales up.
        let (width, height) = plan.drawn_size((target.extent.width, target.extent.height));
        let drawn = vk::Extent2D { width, height };
        self.ensure_targets(TargetSpec {
            extent: drawn,
            hdr: natural || plan.taa || plan.scaled(),
            samples: plan.samples,
            taa: plan.taa,
            deferred: natural,
            reverse_z: false,
            shown: plan.scaled() && target.transfer_dst && self.blits_up,
        })?;
        self.temporal.begin(&plan, drawn);
        // The overlay's layer, drawn when egui's picture changed (before the frame's
        // scopes: twice a second, not every frame); the pixels it will cover opaquely
        // need no tone map.
        #[cfg(feature = "app")]
        let hidden = match (self.overlay.as_mut(), input.overlay.as_ref()) {
            (Some(pass), Some(frame)) => {
                pass.update_textures(&self.pool, frame.textures)?;
                pass.prepare(rec, slot, target.extent, frame)?;
                pass.opaque().filter(|_| target.transfer_dst)
            }
            _ => None,
        };
        #[cfg(not(feature = "app"))]
        let hidden = None;
        let uniforms = self.prepare(&input.request, &plan, input.push, drawn)?;
        let occlusion = plan.occlusion;
        let stamp = stamper(rec, queries);
        let triangles = queries.triangles.as_ref().map(|t| t.pool);
        if let Some(pool) = triangles {
            rec.reset_queries(pool, 0, 1);
        }
        stamp(Mark::Start);
        let colliders = &input.request.colliders()[..uniforms.forces.colliders as usize];
        let questions = input.request.questions();
        self.begin_compute(rec, &uniforms, (colliders, questions));
        if occlusion {
            let targets = self.targets.as_ref().context("draw targets")?;
            self.occlusion
                .record(rec, &self.field, &self.draw.ground, &targets.depth);
        }
        // After the pyramid: the far tiles are tested against it.
        self.record_tiles(rec, (&uniforms, colliders), input.push)?;
        stamp(Mark::Pyramid);
        let asked = (colliders, true, Asked::of(&input.request));
        self.record_simulation(rec, &plan, input.push, asked, &stamp)?;
        let targets = self.targets.as_ref().context("draw targets")?;
        let images = draw_images(targets, &target, drawn, natural);
        self.draw.record(
            rec,
            &self.field,
            &images,
            &plan,
            colliders,
            &stamp,
            triangles,
        );
        stamp(Mark::Resolve);
        if let Some(images) = targets.shaded() {
            self.shade.record(rec, &self.field, images, drawn);
        }
        stamp(Mark::Shade);
        self.copy_counters(rec, queries);
        // What the tone map shows: the history just resolved, or the HDR image.
        let source = if let Some(images) = targets.temporal() {
            let t = &self.temporal;
            let how = (t.read, t.previous.is_none());
            self.temporal_pass.record(rec, images, drawn, how);
            Some(ToneMapSource::History {
                k: 1 - t.read,
                as_drawn: !natural,
            })
        } else if natural || plan.scaled() {
            let hdr = targets.hdr.as_ref().context("HDR image")?;
            Some(ToneMapSource::Drawn {
                image: hdr.image,
                as_drawn: !natural,
            })
        } else {
            None
        };
        if let Some(source) = source {
            let frame = (&target, &uniforms, hidden);
            tone_map(rec, &self.tonemap, targets, (source, drawn), frame);
        }
        self.temporal.end(&plan, &input.request);
        stamp(Mark::ToneMap);
        #[cfg(feature = "app")]
        if let (Some(pass), Some(_)) = (self.overlay.as_mut(), input.overlay.as_ref()) {
            rec.memory_barrier(
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                (
                    S::COLOR_ATTACHMENT_OUTPUT,
                    A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
                ),
            );
            let image = (target.image, target.view, target.extent);
            pass.lay_over(rec, slot, image, hidden)?;
        }
        stamp(Mark::Overlay);
        finish_frame(rec, &target, input.capture);
        Ok(())
    }

    /// The frame's whole block, built once from `request` drawn as `plan` says and
    /// what the renderer knows ([`FrameFacts`]: the target's `extent`, its depth
    /// pyramid, the field, the simulated time after `push`'s steps); the shadow map
    /// takes the plan's size and the ground's grid follows the camera.
    fn prepare(
        &mut self,
        request: &FrameRequest,
        plan: &FramePlan,
        push: SimulatePush,
        extent: vk::Extent2D,
    ) -> Result<FrameUniforms> {
        if let Some(side) = plan.shadows {
            self.shadow
                .resize(&self.ctx, &self.pool, &self.field, side)?;
        }
        self.draw
            .ground
            .follow(request.eye.position, request.eye.view_proj);
        let facts = self.facts(extent, push);
        Ok(self.make_block(request, plan, &facts))
    }

    /// The frame's block from `request` drawn as `plan` says with `facts`, kept as
    /// the newest; a frame with a cutter becomes the newest cut (`last_cut`).
    fn make_block(
        &mut self,
        request: &FrameRequest,
        plan: &FramePlan,
        facts: &FrameFacts,
    ) -> FrameUniforms {
        self.block = request.uniforms(plan, facts);
        if request.colliders().iter().any(Collider::cuts) {
            self.last_cut = facts.time;
        }
        self.block
    }

    /// What the renderer knows of a frame into a target of `extent` after `push`'s
    /// steps: the target's size, its depth pyramid's layout, the field, the time.
    fn facts(&self, extent: vk::Extent2D, push: SimulatePush) -> FrameFacts {
        FrameFacts {
            extent: (extent.width, extent.height),
            hiz: self.occlusion.hiz,
            field: self.field_part(),
            time: shared::sim::simulate::step_time(push.first_step + push.steps),
            reach: self.field.reach,
            roots: self.field.roots,
            last_cut: self.last_cut,
            frame: self.temporal.frame,
            previous: self.temporal.previous,
        }
    }

    /// The block of the newest frame recorded, as the GPU reads it.
    pub fn block(&self) -> &FrameUniforms {
        &self.block
    }

    /// The field's blades: all simulated in a stored field; a tiled field's pool
    /// simulated and the rest generated (`GrassParams::tiled`).
    fn field_part(&self) -> FieldPart {
        FieldPart {
            blades: self.field.blade_count,
            simulated: self.field.simulated,
            tiled: self.tiles.is_some(),
            mixed: self.field.mixed,
        }
    }

    /// A tiled field's tiles for the frame of `push`'s steps with the `colliders`
    /// (nothing for a stored field).
    fn record_tiles(
        &mut self,
        rec: &Recorder,
        (uniforms, colliders): (&FrameUniforms, &[Collider]),
        push: SimulatePush,
    ) -> Result<()> {
        match self.tiles.as_mut() {
            Some(tiles) => {
                let seconds = push.steps as f32 * shared::sim::simulate::STEP_SECONDS;
                tiles.record(rec, &self.field, (uniforms, colliders), seconds)
            }
            None => Ok(()),
        }
    }

    /// Simulate, cull and compact (the clumps first when the natural look's changed),
    /// (the colliders' grid first where there are any), the questions answered and the
    /// contacts marked where the frame `asks`, then the natural look's shadow map,
    /// with the `colliders` where they are `drawn` (not where the caller draws them):
    /// [`Mark::SimulateCull`] and [`Mark::Shadow`] after each.
    fn record_simulation(
        &mut self,
        rec: &Recorder,
        plan: &FramePlan,
        push: SimulatePush,
        (colliders, drawn, asks): (&[Collider], bool, Asked),
        stamp: &dyn Fn(Mark),
    ) -> Result<()> {
        let natural = plan.natural();
        if natural && self.clumped != Some(plan.clumps) {
            self.simulate.record_clumps(rec, &self.field);
            self.clumped = Some(plan.clumps);
        }
        self.record_compute(rec, self.simulate_push(push), (natural, asks))?;
        stamp(Mark::SimulateCull);
        if natural && plan.shadows.is_some() {
            let ground = &self.draw.ground;
            let cast = if drawn { colliders } else { &[] };
            self.shadow.record(rec, &self.field, (ground, cast));
        }
        stamp(Mark::Shadow);
        Ok(())
    }

    /// After the frame of `input` was submitted: frees the overlay textures it
    /// retired.
    #[cfg_attr(not(feature = "app"), allow(unused_variables))]
    pub fn submitted(&mut self, input: &FrameInput) -> Result<()> {
        #[cfg(feature = "app")]
        if let (Some(pass), Some(frame)) = (self.overlay.as_mut(), input.overlay.as_ref()) {
            pass.free_textures(frame.textures)?;
        }
        Ok(())
    }

    /// `push` with a tiled field's layout (its pool's blades thin as the far ones).
    fn simulate_push(&self, push: SimulatePush) -> SimulatePush {
        match &self.tiles {
            Some(tiles) => SimulatePush {
                tiles: tiles.spec().params,
                ..push
            },
            None => SimulatePush {
                tiles: self.stored_maps,
                ..push
            },
        }
    }
}

/// Resets `queries`' timestamps (where the device has them) and returns what writes
/// each [`Mark`], once everything recorded before it is done.
fn stamper<'r>(rec: &'r Recorder, queries: &FrameQueries) -> impl Fn(Mark) + 'r {
    let stamps = queries.timestamps.as_ref().map(|t| t.pool);
    if let Some(pool) = stamps {
        rec.reset_queries(pool, 0, Mark::COUNT);
    }
    move |mark: Mark| {
        if let Some(pool) = stamps {
            rec.write_timestamp(pool, mark as u32, S::BOTTOM_OF_PIPE);
        }
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        let _ = self.ctx.wait_idle();
    }
}
