//! The benchmark's references, measured with the renderer's own field and shader
//! modules: how fast this device copies the blade buffer, and how fast it draws
//! patches tessellated like a blade, or the mesh path's strips (docs/performance.md).

use super::stats::{References, TriangleReference};
use crate::app::headless::Offscreen;
use crate::passes::reference::ReferencePass;
use crate::renderer::{FRAME_STAGES, Renderer, SKY, Target};
use crate::vulkan::query::{TimestampPool, TrianglePool};
use crate::vulkan::{Buffer, Recorder};
use anyhow::{Context as _, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;
use shared::gpu::layout;
use shared::settings::GrassPipeline;

use vk::AccessFlags2 as A;
use vk::PipelineStageFlags2 as S;

/// Tessellation levels the throughput reference is timed at: the fewest and the most
/// segments a blade gets.
const REFERENCE_LEVELS: [f32; 2] = [1.0, shared::cull::lod::MAX_LEVEL];

/// The bandwidth reference and each of `pipelines`' triangle-throughput reference over
/// a field of `blades`.
pub(super) fn measure_references(
    renderer: &mut Renderer,
    offscreen: &Offscreen,
    blades: u32,
    pipelines: &[GrassPipeline],
) -> Result<References> {
    let repeats = 10;
    let pass = ReferencePass::new(
        renderer.context(),
        renderer.modules(),
        &renderer.field,
        renderer.color_format(),
    )?;
    let mut references = References {
        copy_gbs: copy_bandwidth(renderer, &pass, repeats)?,
        ..Default::default()
    };
    let target = offscreen.target();
    for &pipeline in pipelines {
        let mesh = pipeline == GrassPipeline::Mesh;
        let mut timed = Vec::new();
        for level in REFERENCE_LEVELS {
            let Some((ms, counted)) =
                triangle_throughput(renderer, &pass, &target, (blades, level), repeats, mesh)?
            else {
                break;
            };
            // Per patch or strip as counted, else as the rules give it.
            let rule = if mesh {
                2 * shared::draw::meshlet::strip_segments(level)
            } else {
                shared::draw::reference::triangles_per_patch(level)
            };
            let triangles = counted
                .filter(|&t| t > 0)
                .map_or(f64::from(rule), |t| t as f64 / f64::from(blades));
            log::info!(
                "{pipeline:?} triangle reference at level {level}: {triangles} triangles per \
                 blade, {ms:.3} ms"
            );
            timed.push((triangles, ms));
        }
        let [low, high] = timed[..] else { continue };
        let patches = f64::from(blades);
        let (patch_ms, triangle_ms) = TriangleReference::fit(patches, low, high);
        let reference = Some(TriangleReference {
            patch_ms,
            triangle_ms,
            triangles_per_s: patches * high.0 / (high.1 * 1e-3),
        });
        match pipeline {
            GrassPipeline::Tess => references.tess = reference,
            GrassPipeline::Mesh => references.mesh = reference,
        }
    }
    Ok(references)
}

/// Bandwidth reference: GB/s of the copy shader moving every blade (64 bytes read,
/// 64 written) into a scratch buffer made for it, the best of `repeats` timed
/// dispatches; `None` without timestamps.
fn copy_bandwidth(renderer: &Renderer, pass: &ReferencePass, repeats: u32) -> Result<Option<f64>> {
    let (ctx, field) = (renderer.context(), &renderer.field);
    let bytes = u64::from(field.blade_count) * size_of::<shared::Blade>() as u64;
    let scratch = Buffer::new(
        ctx,
        "copy reference",
        bytes,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )?;
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let descriptors = &field.descriptors;
    ctx.wait_idle()?;
    descriptors.write_buffer(layout::BINDING_SCRATCH, storage, scratch.buffer);
    let best = best_time(renderer, repeats, |rec| pass.record_copy(rec, field));
    // Back to the placeholder before the scratch buffer goes.
    ctx.wait_idle()?;
    descriptors.write_buffer(layout::BINDING_SCRATCH, storage, field.visible.buffer);
    Ok(best?.map(|ms| 2.0 * bytes as f64 / (ms * 1e-3) / 1e9))
}

/// Triangle-throughput reference: milliseconds to draw `patches` trivially shaded
/// one-vertex patches at tessellation `level` into `target` (depth tested, on a grid
/// of small cells), or with `mesh` as many of the mesh path's strips of that level,
/// the best of `repeats`, and the triangles generated (pipeline statistics, where the
/// device has them); `None` without timestamps, or without mesh stages for `mesh`.
/// The patches are drawn in chunks of the grass draw's size.
fn triangle_throughput(
    renderer: &mut Renderer,
    pass: &ReferencePass,
    target: &Target,
    (patches, level): (u32, f32),
    repeats: u32,
    mesh: bool,
) -> Result<Option<(f64, Option<u64>)>> {
    if mesh && !pass.has_mesh() {
        return Ok(None);
    }
    let (image, view) = renderer.single_depth(target.extent)?;
    let renderer = &*renderer;
    let field = &renderer.field;
    let push = shared::draw::reference::push(level, target.extent.width, target.extent.height);
    // Each image's barrier names its own kind of access only.
    let color_out = (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
    let depth_tests = (
        S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
        A::DEPTH_STENCIL_ATTACHMENT_WRITE,
    );
    let layouts = (
        vk::ImageLayout::UNDEFINED,
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    );
    let depth_layouts = (
        vk::ImageLayout::UNDEFINED,
        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
    );
    let triangles = TrianglePool::new(renderer.context())?;
    let best = best_time(renderer, repeats, |rec| {
        let color = vk::ImageAspectFlags::COLOR;
        rec.image_barrier(target.image, color, layouts, color_out, color_out);
        let aspect = vk::ImageAspectFlags::DEPTH;
        rec.image_barrier(image, aspect, depth_layouts, depth_tests, depth_tests);
        if let Some(t) = &triangles {
            rec.reset_queries(t.pool, 0, 1);
        }
        rec.begin_rendering(Some((target.view, Some(SKY))), Some(view), target.extent);
        if let Some(t) = &triangles {
            rec.begin_query(t.pool);
        }
        if mesh {
            pass.record_mesh(rec, field, push, patches);
        } else {
            pass.record(rec, field, push, patches, field.chunk_size);
        }
        if let Some(t) = &triangles {
            rec.end_query(t.pool);
        }
        rec.end_rendering();
    })?;
    Ok(best.map(|ms| (ms, triangles.as_ref().and_then(TrianglePool::read))))
}

/// The shortest of `repeats` timed runs of `record`, in milliseconds, each after the
/// previous one's writes; `None` without timestamps.
fn best_time(renderer: &Renderer, repeats: u32, record: impl Fn(&Recorder)) -> Result<Option<f64>> {
    let ctx = renderer.context();
    ctx.wait_idle()?;
    let Some(stamps) = TimestampPool::new(ctx, 2 * repeats.max(1))? else {
        return Ok(None);
    };
    renderer.one_shot(|rec| {
        rec.reset_queries(stamps.pool, 0, stamps.count);
        for r in 0..stamps.count / 2 {
            rec.write_timestamp(stamps.pool, 2 * r, S::BOTTOM_OF_PIPE);
            record(rec);
            rec.write_timestamp(stamps.pool, 2 * r + 1, S::BOTTOM_OF_PIPE);
            rec.memory_barrier(
                (FRAME_STAGES, A::MEMORY_WRITE),
                (FRAME_STAGES, A::MEMORY_READ | A::MEMORY_WRITE),
            );
        }
    })?;
    let ms = stamps.read_all_ms().context("reference timestamps")?;
    let best = ms
        .chunks(2)
        .map(|pair| pair[1] - pair[0])
        .fold(f64::MAX, f64::min);
    Ok(Some(best))
}
