//! The benchmark's results on stdout (the table and the references) and in the CSV
//! file.

use super::stats::{Point, References, Spread, compute_gbs};
use crate::cli::{BenchArgs, Common};
use anyhow::Result;

/// The compute pass against the copy shader's bandwidth, and the grass draw against
/// the throughput reference, for every point of the largest count, `blades`.
pub fn print_references(blades: u32, r: &References, points: &[Point]) {
    let mut lines = Vec::new();
    if let Some(copy) = r.copy_gbs {
        lines.push(format!(
            "bandwidth reference: the copy shader moves {copy:.0} GB/s over {blades} blades"
        ));
    }
    for (name, t) in [("tessellation", &r.tess), ("mesh", &r.mesh)] {
        if let Some(t) = t {
            lines.push(format!(
                "{name} triangle reference: {:.0} M triangles/s at {} segments; {:.2} ns per \
                 blade + {:.3} ns per triangle",
                t.triangles_per_s / 1e6,
                shared::cull::lod::MAX_SEGMENTS,
                t.patch_ms * 1e6,
                t.triangle_ms * 1e6
            ));
        }
    }
    for line in &lines {
        println!("{line}");
        log::info!("{line}");
    }
    for p in points.iter().filter(|p| p.blades == blades) {
        let mut line = format!("  {:<20}", format!("{:?}", p.config));
        if let Some(copy) = r.copy_gbs {
            let gbs = compute_gbs(p);
            line += &format!(
                " simulate+cull {gbs:>6.0} GB/s ({:>5.1} % of the copy)",
                100.0 * gbs / copy
            );
        }
        // (Nothing to compare where the compute rasterizer took every blade.)
        if let (Some(triangles), Some(t), true) =
            (p.triangles, r.triangles(p.pipeline), p.drawn > 0.0)
        {
            let ideal = t.grass_ms(p.drawn, triangles);
            line += &format!(
                "; {:?} grass {:.1} M triangles, reference {ideal:.3} ms ({:>5.1} % of its speed)",
                p.pipeline,
                triangles / 1e6,
                100.0 * ideal / p.grass.median
            );
        }
        println!("{line}");
    }
}

/// The table of `points` on stdout, after a line naming the device, the image size,
/// the camera and the frames per point.
pub fn print_table(device: &str, args: &BenchArgs, points: &[Point]) {
    println!(
        "{device}, {}x{}, camera {:?}, {} frames per point (median, p95 in brackets; \
         diff: mean difference from no culling and no LOD, 0-255)",
        args.width, args.height, args.camera, args.frames
    );
    println!(
        "{:<8} {:<5} {:>6} {:<20} {:>9} {:>9} {:>9} {:>11} {:>18} {:>18} {:>18} {:>18} {:>18} {:>6} {:>8}",
        "look",
        "pipe",
        "raster",
        "config",
        "blades",
        "drawn",
        "compute",
        "triangles",
        "simulate+cull ms",
        "grass ms",
        "compute raster ms",
        "GPU frame ms",
        "CPU frame ms",
        "diff",
        "ns/blade"
    );
    let cell = |s: Spread| format!("{:.3} ({:.3})", s.median, s.p95);
    for p in points {
        println!(
            "{:<8} {:<5} {:>6} {:<20} {:>9} {:>9.0} {:>9.0} {:>11} {:>18} {:>18} {:>18} {:>18} {:>18} {:>6.2} {:>8}",
            format!("{:?}", p.look),
            format!("{:?}", p.pipeline).to_lowercase(),
            p.compute_below,
            format!("{:?}", p.config),
            p.blades,
            p.drawn,
            p.compute_drawn,
            p.triangles.map_or("-".into(), |t| format!("{t:.0}")),
            cell(p.simulate_cull),
            cell(p.grass),
            cell(p.raster),
            cell(p.gpu),
            cell(p.cpu),
            p.difference,
            ns_per_drawn_blade(p).map_or("-".into(), |ns| format!("{ns:.2}"))
        );
    }
    print_tiled(points);
}

/// A tiled field's line per point: the world's blades, the far tiles and blades in
/// view, and the GPU frame's 99th percentile against its median (the tiled world's targets).
pub fn print_tiled(points: &[Point]) {
    for p in points.iter().filter(|p| p.potential > 0.0) {
        println!(
            "tiled field, {:?} look: {:.0} M blades in the world; {:.0} far tiles in view with              {:.0} blades generated (medians); GPU frame median {:.3} ms, p99 {:.3} ms ({:.2}x)",
            p.look,
            p.potential / 1e6,
            p.far_tiles,
            p.far_blades,
            p.gpu.median,
            p.gpu.p99,
            p.gpu.p99 / p.gpu.median.max(1e-9)
        );
    }
}

/// The grass pass's median time per blade it drew, in nanoseconds; `None` where the
/// hardware drew none (the compute rasterizer took them all).
pub fn ns_per_drawn_blade(p: &Point) -> Option<f64> {
    (p.drawn > 0.0).then(|| p.grass.median * 1e6 / p.drawn)
}

/// The compute rasterizer's median time (depth copy, clear and far blades) per blade
/// it drew, per pixel its blades covered and per pixel it wrote, in nanoseconds;
/// `None` where it drew none. A covered pixel costs a depth test, a written one an
/// atomic too: where near grass hides the far field (the edge camera) few are
/// written, and the time per covered pixel is the one to read.
pub fn raster_costs(p: &Point) -> Option<(f64, f64, f64)> {
    (p.compute_drawn > 0.0).then(|| {
        let ns = p.raster.median * 1e6;
        (
            ns / p.compute_drawn,
            ns / p.raster_covered.max(1.0),
            ns / p.raster_written.max(1.0),
        )
    })
}

/// For each point where the compute rasterizer drew blades: its time, its blades and
/// pixels, and what one of each cost.
pub fn print_raster(points: &[Point]) {
    for p in points {
        let Some((per_blade, per_covered, per_written)) = raster_costs(p) else {
            continue;
        };
        println!(
            "compute rasterizer, {:?} {:?} {} blades at {} px: {:.3} ms for {:.0} blades \
             ({:.0} % of those drawn), {:.0} pixels covered, {:.0} written \
             ({:.0} %); {per_blade:.2} ns per blade, {per_covered:.2} ns per pixel covered, \
             {per_written:.2} ns per pixel written",
            p.look,
            p.config,
            p.blades,
            p.compute_below,
            p.raster.median,
            p.compute_drawn,
            100.0 * p.compute_drawn / (p.compute_drawn + p.drawn).max(1.0),
            p.raster_covered,
            p.raster_written,
            100.0 * p.raster_written / p.raster_covered.max(1.0),
        );
    }
}

/// Each point with walkers or mowers against the same point without them
/// (`--walkers`, `--mowers`): the
/// whole frame and the compute pass, GPU medians.
pub fn print_walkers(points: &[Point]) {
    let pairs: Vec<(&Point, &Point)> = points
        .iter()
        .filter(|p| p.walkers > 0 || p.mowers > 0)
        .filter_map(|crowd| {
            points
                .iter()
                .find(|p| {
                    p.walkers == 0
                        && p.mowers == 0
                        && p.look == crowd.look
                        && p.config == crowd.config
                        && p.blades == crowd.blades
                        && p.pipeline == crowd.pipeline
                        && p.compute_below == crowd.compute_below
                })
                .map(|none| (none, crowd))
        })
        .collect();
    if pairs.is_empty() {
        return;
    }
    println!(
        "walkers against none (GPU ms, medians): {:<20} {:>8} {:>9} {:>8} {:>8} {:>7} | {:>9} {:>9} {:>9}",
        "config", "look", "blades", "none", "walkers", "ratio", "sim none", "sim with", "collided"
    );
    for (none, crowd) in pairs {
        println!(
            "{:<20} {:>8} {:>9} {:>8.3} {:>8.3} {:>7.3} | {:>9.3} {:>9.3} {:>9.0}   ({} walkers, {} mowers)",
            format!("{:?}", none.config),
            format!("{:?}", none.look),
            none.blades,
            none.gpu.median,
            crowd.gpu.median,
            crowd.gpu.median / none.gpu.median.max(1e-9),
            none.simulate_cull.median,
            crowd.simulate_cull.median,
            crowd.collided,
            crowd.walkers,
            crowd.mowers
        );
    }
}

/// With both looks measured: for each count and configuration, the natural look's GPU
/// frame against the paper's, and the natural look's passes.
pub fn print_looks(points: &[Point]) {
    use shared::settings::Look;
    let pairs: Vec<(&Point, &Point)> = points
        .iter()
        .filter(|p| p.look == Look::Paper)
        .filter_map(|paper| {
            points
                .iter()
                .find(|n| {
                    n.look == Look::Natural
                        && n.config == paper.config
                        && n.blades == paper.blades
                        && n.pipeline == paper.pipeline
                })
                .map(|natural| (paper, natural))
        })
        .collect();
    if pairs.is_empty() {
        return;
    }
    println!(
        "natural against paper look (GPU ms, medians): {:<20} {:>9} {:>8} {:>8} {:>6} | {:>7} {:>7} {:>7} {:>7} {:>9}",
        "config",
        "blades",
        "paper",
        "natural",
        "ratio",
        "shadow",
        "ground",
        "grass",
        "resolve",
        "tone map"
    );
    for (paper, natural) in pairs {
        let ratio = natural.gpu.median / paper.gpu.median.max(1e-9);
        let line = format!(
            "{:<20} {:>9} {:>8.3} {:>8.3} {:>6.2} | {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>9.3}",
            format!("{:?}", paper.config),
            paper.blades,
            paper.gpu.median,
            natural.gpu.median,
            ratio,
            natural.shadow.median,
            natural.ground.median,
            natural.grass.median,
            natural.resolve.median,
            natural.tone_map.median
        );
        println!("  {line}");
        log::info!("looks: {line}");
    }
}

/// Writes `points` and the references `r` to the CSV file at `path`, one line per
/// point, creating its folder if need be.
pub fn write_csv(
    path: &std::path::Path,
    device: &str,
    common: &Common,
    args: &BenchArgs,
    points: &[Point],
    r: &References,
) -> Result<()> {
    let mut out = String::from(
        "device,scene,camera,width,height,frames,config,blades,drawn,\
         cpu_ms_median,cpu_ms_p95,gpu_ms_median,gpu_ms_p95,\
         uploads_pyramid_ms_median,simulate_cull_ms_median,simulate_cull_ms_p95,\
         ground_ms_median,grass_ms_median,grass_ms_p95,triangles,mean_difference,\
         simulate_cull_gb_s,copy_reference_gb_s,grass_reference_ms,\
         look,msaa,shadow_ms_median,resolve_ms_median,tone_map_ms_median,pipeline,\
         grass_ns_per_drawn_blade,compute_raster_below,drawn_by_compute,\
         raster_ms_median,raster_pixels_covered,raster_pixels_written,\
         raster_ns_per_blade,raster_ns_per_pixel_covered,raster_ns_per_pixel_written,\
         gpu_ms_p99,potential_blades,far_tiles,far_blades,aa,shade_ms_median,render_scale,shadow_casters,\
         walkers,mowers,collided\n",
    );
    let optional =
        |v: Option<f64>, digits: usize| v.map_or(String::new(), |v| format!("{v:.digits$}"));
    for p in points {
        let reference_ms = p
            .triangles
            .zip(r.triangles(p.pipeline))
            .map(|(triangles, t)| t.grass_ms(p.drawn, triangles));
        let costs = raster_costs(p);
        out += &format!(
            "\"{device}\",{},{:?},{},{},{},{:?},{},{:.0},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{},{:.3},{:.0},{},{},{:?},{},{:.4},{:.4},{:.4},{},{},{},{:.0},{:.4},{:.0},{:.0},{},{},{},{:.4},{:.0},{:.0},{:.0},{},{:.4},{},{:.0},{},{},{:.0}\n",
            common.scene,
            args.camera,
            args.width,
            args.height,
            args.frames,
            p.config,
            p.blades,
            p.drawn,
            p.cpu.median,
            p.cpu.p95,
            p.gpu.median,
            p.gpu.p95,
            p.pyramid.median,
            p.simulate_cull.median,
            p.simulate_cull.p95,
            p.ground.median,
            p.grass.median,
            p.grass.p95,
            optional(p.triangles, 0),
            p.difference,
            compute_gbs(p),
            optional(r.copy_gbs, 0),
            optional(reference_ms, 4),
            p.look,
            p.samples,
            p.shadow.median,
            p.resolve.median,
            p.tone_map.median,
            format!("{:?}", p.pipeline).to_lowercase(),
            optional(ns_per_drawn_blade(p), 3),
            p.compute_below,
            p.compute_drawn,
            p.raster.median,
            p.raster_covered,
            p.raster_written,
            optional(costs.map(|c| c.0), 3),
            optional(costs.map(|c| c.1), 3),
            optional(costs.map(|c| c.2), 3),
            p.gpu.p99,
            p.potential,
            p.far_tiles,
            p.far_blades,
            format!("{:?}", p.aa).to_lowercase(),
            p.shade.median,
            p.render_scale,
            p.casters,
            p.walkers,
            p.mowers,
            p.collided,
        );
    }
    crate::files::write(path, out.as_bytes())?;
    Ok(())
}
