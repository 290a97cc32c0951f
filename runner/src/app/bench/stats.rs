//! The benchmark's plain data and arithmetic: percentiles of samples, the measured
//! points of the sweep, the device's references and the bandwidth of the compute
//! pass. No renderer and no printing.

use crate::cli::BenchConfig;
use shared::settings::GrassPipeline;
use shared::settings::Look;

/// The median, 95th and 99th percentiles of some samples.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Spread {
    /// 50th percentile.
    pub median: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
}

impl Spread {
    /// Nearest-rank percentiles of `samples` (zero when empty).
    pub fn of(samples: &[f64]) -> Self {
        let mut sorted: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f64::total_cmp);
        let rank = |p: f64| {
            if sorted.is_empty() {
                0.0
            } else {
                let i = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
                sorted[i - 1]
            }
        };
        Self {
            median: rank(0.5),
            p95: rank(0.95),
            p99: rank(0.99),
        }
    }
}

/// One measured point of the sweep.
#[derive(Clone, Debug)]
pub struct Point {
    /// The look.
    pub look: Look,
    /// The grass pipeline.
    pub pipeline: shared::settings::GrassPipeline,
    /// Samples per pixel.
    pub samples: u32,
    /// The anti-aliasing.
    pub aa: shared::settings::Antialiasing,
    /// The share of the output's width and height the scene was drawn at.
    pub render_scale: f32,
    /// Blades shorter on screen than this (pixels) went to the compute rasterizer;
    /// 0: off.
    pub compute_below: f32,
    /// Median blades the compute rasterizer drew.
    pub compute_drawn: f64,
    /// Median pixels its blades covered on the target.
    pub raster_covered: f64,
    /// Median pixels it wrote (in front of the hardware's depth and of the far blade
    /// the pixel held).
    pub raster_written: f64,
    /// Configuration.
    pub config: BenchConfig,
    /// Walkers wandering the field (`--walkers`).
    pub walkers: u32,
    /// Mowers cutting it (`--mowers`).
    pub mowers: u32,
    /// Blades in the field (a tiled field's room for them).
    pub blades: u32,
    /// A tiled field's blades in the world at full density; 0 for a stored field.
    pub potential: f64,
    /// Median far tiles in view and the far blades generated for them (tiled).
    pub far_tiles: f64,
    /// Median far blades generated (tiled).
    pub far_blades: f64,
    /// Median blades drawn into the sun's shadow map (every cascade's casters).
    pub casters: f64,
    /// Median blades handed to the collision pass (within reach of a collider).
    pub collided: f64,
    /// Blades drawn (median).
    pub drawn: f64,
    /// CPU time between frames.
    pub cpu: Spread,
    /// Whole frame on the GPU.
    pub gpu: Spread,
    /// Uniform uploads, depth pre-pass and pyramid.
    pub pyramid: Spread,
    /// Simulate, cull, compact.
    pub simulate_cull: Spread,
    /// The sun's shadow map.
    pub shadow: Spread,
    /// Ground.
    pub ground: Spread,
    /// Grass.
    pub grass: Spread,
    /// The compute rasterizer (depth copy, clear, far blades).
    pub raster: Spread,
    /// The compute rasterizer's resolve and the multisample resolve.
    pub resolve: Spread,
    /// Temporal resolve, sky and tone map.
    pub tone_map: Spread,
    /// The natural look's shading after the draw.
    pub shade: Spread,
    /// Triangles the grass draw generated (median; pipeline statistics, where the
    /// device has them).
    pub triangles: Option<f64>,
    /// Mean difference from the same still frame with no culling and no LOD, in 8-bit
    /// levels averaged over the pixels' colour channels.
    pub difference: f64,
}

/// What this device does at most, measured in the same run with the largest field.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct References {
    /// The copy shader's bandwidth, GB/s.
    pub copy_gbs: Option<f64>,
    /// The tessellation path's triangle reference.
    pub tess: Option<TriangleReference>,
    /// The mesh path's triangle reference.
    pub mesh: Option<TriangleReference>,
}

impl References {
    /// The triangle reference of `pipeline`, if it was measured.
    pub fn triangles(&self, pipeline: GrassPipeline) -> Option<&TriangleReference> {
        match pipeline {
            GrassPipeline::Tess => self.tess.as_ref(),
            GrassPipeline::Mesh => self.mesh.as_ref(),
        }
    }
}

/// One pipeline's triangle-throughput reference: what it costs per blade (a patch or
/// a strip) and per triangle with nothing to compute.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct TriangleReference {
    /// Cost per patch or strip, ms.
    pub patch_ms: f64,
    /// Cost per triangle, ms.
    pub triangle_ms: f64,
    /// Best triangles per second (at the highest level).
    pub triangles_per_s: f64,
}

impl TriangleReference {
    /// Per-patch and per-triangle cost from the reference's times `t_low` and `t_high`
    /// (ms) for `patches` patches of `low` and `high` triangles each:
    /// t = patches · (patch + triangles · triangle). Neither is below zero (timing
    /// noise on a software device can make a straight fit say so).
    pub fn fit(patches: f64, (low, t_low): (f64, f64), (high, t_high): (f64, f64)) -> (f64, f64) {
        let triangle = ((t_high - t_low) / (patches * (high - low))).max(0.0);
        let patch = (t_low / patches - low * triangle).max(0.0);
        (patch, triangle)
    }

    /// What the reference would take to draw `patches` patches making `triangles`.
    pub fn grass_ms(&self, patches: f64, triangles: f64) -> f64 {
        patches * self.patch_ms + triangles * self.triangle_ms
    }
}

/// Mean absolute difference of two RGBA8 images of one size, over the pixels' red,
/// green and blue channels, in 8-bit levels (0 to 255).
pub fn mean_difference(a: &[u8], b: &[u8]) -> f64 {
    let (sum, count) = a
        .as_chunks::<4>()
        .0
        .iter()
        .zip(b.as_chunks::<4>().0)
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c]) as u64))
        .fold((0u64, 0u64), |(s, n), d| (s + d, n + 1));
    if count == 0 {
        0.0
    } else {
        sum as f64 / count as f64
    }
}

/// Bytes the simulate-and-cull pass moves for `blades` blades of which `drawn` survive:
/// each blade and its collision strength read (68 bytes), its curve (`v1`, `v2`: the
/// blade's first 32 bytes) and strength written (36 bytes), each survivor's index
/// written (4 bytes).
pub fn compute_bytes(blades: u32, drawn: f64) -> f64 {
    (68.0 + 36.0) * f64::from(blades) + 4.0 * drawn
}

/// The simulate-and-cull pass's bandwidth at point `p`, GB/s.
pub fn compute_gbs(p: &Point) -> f64 {
    compute_bytes(p.blades, p.drawn) / (p.simulate_cull.median * 1e-3) / 1e9
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compute_bytes_by_hand() {
        // 1,000 blades × 104 bytes + 500 survivors × 4 bytes.
        assert_eq!(compute_bytes(1000, 500.0), 104_000.0 + 2_000.0);
    }

    #[test]
    fn mean_difference_by_hand() {
        let black = [0, 0, 0, 255, 0, 0, 0, 255];
        // One pixel off by (30, 60, 90), alpha ignored: 180 / 6 channels.
        let other = [30, 60, 90, 0, 0, 0, 0, 255];
        assert_eq!(mean_difference(&black, &other), 30.0);
        assert_eq!(mean_difference(&other, &other), 0.0);
        assert_eq!(mean_difference(&[], &[]), 0.0);
    }

    #[test]
    fn reference_costs_from_two_levels() {
        // 1,000 patches: 0.01 ms each, plus 0.001 ms per triangle.
        let t = |triangles: f64| 1000.0 * (0.01 + triangles * 0.001);
        let (patch, triangle) = TriangleReference::fit(1000.0, (2.0, t(2.0)), (18.0, t(18.0)));
        assert!((patch - 0.01).abs() < 1e-12 && (triangle - 0.001).abs() < 1e-12);
        let r = TriangleReference {
            patch_ms: patch,
            triangle_ms: triangle,
            ..Default::default()
        };
        assert!((r.grass_ms(500.0, 4000.0) - (5.0 + 4.0)).abs() < 1e-9);
        // Noise that makes the higher level faster is no negative cost.
        assert_eq!(
            TriangleReference::fit(10.0, (2.0, 5.0), (18.0, 4.0)),
            (0.5, 0.0)
        );
        // Each pipeline's points take their own reference.
        let both = References {
            tess: Some(r),
            mesh: None,
            ..Default::default()
        };
        assert_eq!(both.triangles(GrassPipeline::Tess), Some(&r));
        assert_eq!(both.triangles(GrassPipeline::Mesh), None);
    }

    #[test]
    fn percentiles_by_nearest_rank() {
        let samples: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(
            Spread::of(&samples),
            Spread {
                median: 10.0,
                p95: 19.0,
                p99: 20.0
            }
        );
        assert_eq!(
            Spread::of(&[3.0]),
            Spread {
                median: 3.0,
                p95: 3.0,
                p99: 3.0
            }
        );
        assert_eq!(Spread::of(&[]), Spread::default());
        // Order and non-finite samples do not matter.
        let shuffled = [5.0, f64::NAN, 1.0, 4.0, 2.0, 3.0];
        assert_eq!(Spread::of(&shuffled).median, 3.0);
    }
}
