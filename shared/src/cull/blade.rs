//! The culling tests of the compute pass (paper section 4.2): a blade that fails any
//! enabled test is not drawn this frame.

use crate::Blade;
use crate::cull::hiz::{HiZLayout, occluded};
use spirv_std::glam::{Mat4, Vec3, Vec4};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Thresholds of the tests, as the frame block carries them.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CullParams {
    /// Orientation: cull when |dir_view · t1| exceeds this (paper: 0.9).
    pub orientation_threshold: f32,
    /// Frustum: clip-space slack around the view volume for the blade's width.
    pub frustum_tolerance: f32,
    /// Distance: blades farther than this (projected on the ground) are culled.
    pub max_distance: f32,
    /// Distance: number of buckets n thinning the field with distance.
    pub buckets: u32,
    /// Which tests run: a mask of [`ORIENTATION`], [`FRUSTUM`], [`DISTANCE`],
    /// [`OCCLUSION`].
    pub enabled: u32,
    /// Orientation: an edge-on blade is removed only where its sliver is narrower
    /// than this many pixels ([`edge_on_pixels`]); 0 removes every one (the paper).
    pub edge_on_pixels: f32,
    /// The camera's focal length in pixels (`cull::lod::focal_pixels`), for
    /// [`edge_on_pixels`].
    pub focal_pixels: f32,
    /// Padding: the frame block's next member starts 16-byte aligned.
    pub padding: [u32; 2],
}

/// Bit of [`CullParams::enabled`] for the orientation test.
pub const ORIENTATION: u32 = 1;
/// Bit of [`CullParams::enabled`] for the view-frustum test.
pub const FRUSTUM: u32 = 2;
/// Bit of [`CullParams::enabled`] for the distance test.
pub const DISTANCE: u32 = 4;
/// Bit of [`CullParams::enabled`] for the occlusion test (see [`crate::cull::hiz`]).
pub const OCCLUSION: u32 = 8;
/// Every test.
pub const ALL: u32 = ORIENTATION | FRUSTUM | DISTANCE | OCCLUSION;
/// The tests in the order they run, which is the order of their counters.
pub const TESTS: [u32; 4] = [ORIENTATION, FRUSTUM, DISTANCE, OCCLUSION];
/// Names of [`TESTS`], for logs and the overlay.
pub const TEST_NAMES: [&str; 4] = ["orientation", "frustum", "distance", "occlusion"];

/// Outcome of [`cull_outcome`]: the blade is drawn.
pub const KEPT: u32 = 0;
/// Outcome: removed by the orientation test.
pub const BY_ORIENTATION: u32 = 1;
/// Outcome: removed by the frustum test (it passed the orientation test).
pub const BY_FRUSTUM: u32 = 2;
/// Outcome: removed by the distance test (it passed the tests before).
pub const BY_DISTANCE: u32 = 3;
/// Outcome: removed by the occlusion test (it passed every other test).
pub const BY_OCCLUSION: u32 = 4;

/// |dir_view · t1| with dir_view the camera-to-root direction projected onto the
/// blade's ground plane: 1 when the blade is seen exactly edge-on.
pub fn orientation_alignment(blade: &Blade, camera: Vec3) -> f32 {
    let up = blade.up_dir();
    let view = blade.root() - camera;
    let view = (view - up * view.dot(up)).normalize_or_zero();
    view.dot(blade.width_dir()).abs()
}

/// The width in pixels of a blade seen from `camera` at `alignment`
/// ([`orientation_alignment`]): w·√(1 − a²)·f/d, its width across the view, f the
/// focal length in pixels and d the distance to its midpoint.
pub fn edge_on_pixels(blade: &Blade, camera: Vec3, alignment: f32, focal_pixels: f32) -> f32 {
    let distance = (blade.midpoint() - camera).length().max(1e-6);
    let across = (1.0 - alignment * alignment).max(0.0).sqrt();
    blade.width() * across * focal_pixels / distance
}

/// Orientation test: a blade seen edge-on (|dir_view · t1| above the threshold, the
/// paper's test) covers almost no pixels. Near the camera such a blade is still a
/// sliver several pixels wide, whose removal shows: it is removed only where it is
/// narrower than `p.edge_on_pixels` on screen (every one where that is 0).
pub fn cull_orientation(blade: &Blade, camera: Vec3, p: &CullParams) -> bool {
    let alignment = orientation_alignment(blade, camera);
    alignment > p.orientation_threshold && under_edge_on_guard(blade, camera, alignment, p)
}

/// Whether a blade seen from `camera` at `alignment` is narrow enough for the
/// orientation test to remove it once edge-on: narrower on screen than
/// `p.edge_on_pixels` ([`edge_on_pixels`]), or any blade where that is 0 (the paper).
pub fn under_edge_on_guard(blade: &Blade, camera: Vec3, alignment: f32, p: &CullParams) -> bool {
    p.edge_on_pixels <= 0.0
        || edge_on_pixels(blade, camera, alignment, p.focal_pixels) < p.edge_on_pixels
}

/// Signed distance of a clip-space point to the nearest plane of the view volume
/// slackened by `tolerance`: ≥ 0 inside. The planes are −(w + tol) ≤ x, y ≤ w + tol and
/// 0 ≤ z ≤ w (Vulkan depth range).
pub fn clip_margin(clip: Vec4, tolerance: f32) -> f32 {
    let limit = clip.w + tolerance;
    (limit - clip.x.abs())
        .min(limit - clip.y.abs())
        .min(clip.z)
        .min(clip.w - clip.z)
}

/// A clip-space point is inside the (slackened) view volume when its
/// [`clip_margin`] is not negative.
pub fn clip_inside(clip: Vec4, tolerance: f32) -> bool {
    clip_margin(clip, tolerance) >= 0.0
}

/// View-frustum test: cull only when v0, the curve midpoint m and v2 are all outside.
pub fn cull_frustum(blade: &Blade, view_proj: Mat4, tolerance: f32) -> bool {
    let inside = |p: Vec3| clip_inside(view_proj * p.extend(1.0), tolerance);
    !(inside(blade.root()) || inside(blade.midpoint()) || inside(blade.tip()))
}

/// dproj = |v0 − c − up·((v0 − c)·up)|: camera distance along the blade's ground.
pub fn projected_distance(blade: &Blade, camera: Vec3) -> f32 {
    let up = blade.up_dir();
    let d = blade.root() - camera;
    (d - up * d.dot(up)).length()
}

/// n·(1 − dproj/dmax): where distance `dproj` falls among the n buckets.
pub fn distance_bucket_position(dproj: f32, max_distance: f32, buckets: u32) -> f32 {
    buckets as f32 * (1.0 - dproj / max_distance)
}

/// The highest bucket kept at distance `dproj`: floor(n·(1 − dproj/dmax)). Negative
/// beyond dmax, where nothing is kept.
pub fn distance_bucket_limit(dproj: f32, max_distance: f32, buckets: u32) -> f32 {
    distance_bucket_position(dproj, max_distance, buckets).floor()
}

/// Distance test: beyond dmax cull; nearer, blade `id` in bucket (id mod n) is culled
/// when its bucket exceeds floor(n·(1 − dproj/dmax)), thinning the far field evenly.
pub fn cull_distance(
    blade: &Blade,
    id: u32,
    camera: Vec3,
    max_distance: f32,
    buckets: u32,
) -> bool {
    let dproj = projected_distance(blade, camera);
    dproj > max_distance
        || (id % buckets.max(1)) as f32 > distance_bucket_limit(dproj, max_distance, buckets)
}

/// The enabled tests in order, cheapest first: [`KEPT`], or the `BY_*` outcome of the
/// first test that removes blade `id`. Every blade gets exactly one outcome, so the
/// per-outcome counts add up to the blade count. `pyramid` and `hiz` are this
/// frame's occluder depth pyramid; an empty layout keeps every blade.
pub fn cull_outcome(
    blade: &Blade,
    id: u32,
    camera: Vec3,
    view_proj: Mat4,
    p: &CullParams,
    pyramid: &[f32],
    hiz: &HiZLayout,
) -> u32 {
    let same = |b: &Blade| *b;
    cull_outcome_as_drawn(blade, same, id, camera, view_proj, p, pyramid, hiz)
}

/// [`cull_outcome`] for a look that draws a blade otherwise than it is stored (the
/// natural look leans and grows it by its clump): the orientation test takes the
/// stored blade (its orientation and width are the drawn one's), and the blades it
/// keeps are tested as `drawn(blade)` gives them, so a blade it removes costs nothing
/// more.
#[allow(clippy::too_many_arguments)]
pub fn cull_outcome_as_drawn(
    blade: &Blade,
    drawn: impl Fn(&Blade) -> Blade,
    id: u32,
    camera: Vec3,
    view_proj: Mat4,
    p: &CullParams,
    pyramid: &[f32],
    hiz: &HiZLayout,
) -> u32 {
    if p.enabled & ORIENTATION != 0 && cull_orientation(blade, camera, p) {
        return BY_ORIENTATION;
    }
    let blade = &drawn(blade);
    if p.enabled & FRUSTUM != 0 && cull_frustum(blade, view_proj, p.frustum_tolerance) {
        BY_FRUSTUM
    } else if p.enabled & DISTANCE != 0
        && cull_distance(blade, id, camera, p.max_distance, p.buckets)
    {
        BY_DISTANCE
    } else if p.enabled & OCCLUSION != 0 && occluded(blade, view_proj, pyramid, hiz) {
        BY_OCCLUSION
    } else {
        KEPT
    }
}

/// The enabled tests without occluders: true when blade `id` is to be drawn.
pub fn is_visible(blade: &Blade, id: u32, camera: Vec3, view_proj: Mat4, p: &CullParams) -> bool {
    cull_outcome(blade, id, camera, view_proj, p, &[], &HiZLayout::default()) == KEPT
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A blade at the origin, up = +Y, θ = 0: width along +X.
    fn blade() -> Blade {
        Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0)
    }

    /// The paper's orientation test at `threshold`: every edge-on blade removed.
    fn paper(threshold: f32) -> CullParams {
        CullParams {
            orientation_threshold: threshold,
            ..Default::default()
        }
    }

    #[test]
    fn orientation_on_both_sides_of_the_threshold() {
        let b = blade();
        let cull_orientation =
            |b: &Blade, camera, threshold| cull_orientation(b, camera, &paper(threshold));
        // Camera along the width axis, high up: projected view is ±X → edge-on.
        assert!(cull_orientation(&b, Vec3::new(-10.0, 50.0, 0.0), 0.9));
        // Camera in front: view along Z, perpendicular to the width → kept.
        assert!(!cull_orientation(&b, Vec3::new(0.0, 1.0, -10.0), 0.9));
        // |cos| of 20° = 0.94 > 0.9 culled; of 30° = 0.87 kept.
        let at = |deg: f32| {
            let a = deg.to_radians();
            Vec3::new(-a.cos(), 0.0, -a.sin()) * 10.0
        };
        assert!(cull_orientation(&b, at(20.0), 0.9));
        assert!(!cull_orientation(&b, at(30.0), 0.9));
        // Straight above: no projected direction, never culled.
        assert!(!cull_orientation(&b, Vec3::new(0.0, 10.0, 0.0), 0.9));
    }

    #[test]
    fn an_edge_on_blade_wider_than_the_guard_is_kept() {
        let b = blade();
        // 20 degrees off the width axis, 10 units away: |cos 20°| = 0.94 > 0.9, the
        // width across the view 0.1·sin 20° = 0.0342; at a focal length of 1,000
        // pixels and 10.11 units from the midpoint (0, 1.5, 0): 3.38 pixels.
        let a = 20f32.to_radians();
        let camera = Vec3::new(-a.cos(), 0.0, -a.sin()) * 10.0;
        let d = (b.midpoint() - camera).length();
        assert!((d - 10.11).abs() < 0.01, "{d}");
        let px = edge_on_pixels(&b, camera, orientation_alignment(&b, camera), 1000.0);
        assert!((px - 3.382).abs() < 1e-3, "{px}");
        let guard = |pixels| CullParams {
            edge_on_pixels: pixels,
            focal_pixels: 1000.0,
            ..paper(0.9)
        };
        assert!(!cull_orientation(&b, camera, &guard(2.0)));
        assert!(cull_orientation(&b, camera, &guard(4.0)));
        assert!(cull_orientation(&b, camera, &guard(0.0)));
        // Ten times as far: 0.34 pixels, under a guard of 2.
        assert!(cull_orientation(&b, camera * 10.0, &guard(2.0)));
        // Not edge-on: kept whatever the guard.
        assert!(!cull_orientation(
            &b,
            Vec3::new(0.0, 1.0, -100.0),
            &guard(2.0)
        ));
    }

    #[test]
    fn the_tests_after_orientation_take_the_blade_as_drawn() {
        // Identity "clip space": the stored blade (x 5 to 5) is outside |x| <= 1.5,
        // the drawn one moved to x = 0 inside.
        let stored = Blade::at_rest(Vec3::new(5.0, 0.0, 0.5), Vec3::Y, 0.0, 0.5, 0.1, 10.0);
        let moved = |b: &Blade| {
            let back = Vec3::new(-5.0, 0.0, 0.0);
            let mut m = b.with_curve(b.guide() + back, b.tip() + back);
            m.v0 = (b.root() + back).extend(b.orientation());
            m
        };
        let p = CullParams {
            frustum_tolerance: 0.5,
            enabled: FRUSTUM,
            ..Default::default()
        };
        let (camera, view_proj) = (Vec3::new(0.0, 0.0, -10.0), Mat4::IDENTITY);
        let none = HiZLayout::default();
        assert_eq!(
            cull_outcome(&stored, 0, camera, view_proj, &p, &[], &none),
            BY_FRUSTUM
        );
        let drawn = cull_outcome_as_drawn(&stored, moved, 0, camera, view_proj, &p, &[], &none);
        assert_eq!(drawn, KEPT);
        // A blade the orientation test removes is never dressed.
        let calls = core::cell::Cell::new(0);
        let counted = |b: &Blade| {
            calls.set(calls.get() + 1);
            *b
        };
        let edge_on = CullParams {
            orientation_threshold: 0.9,
            enabled: ORIENTATION | FRUSTUM,
            ..Default::default()
        };
        let along = Vec3::new(-10.0, 0.5, 0.5);
        let outcome =
            cull_outcome_as_drawn(&stored, counted, 0, along, view_proj, &edge_on, &[], &none);
        assert_eq!((outcome, calls.get()), (BY_ORIENTATION, 0));
    }

    #[test]
    fn clip_inside_on_both_sides_of_each_plane() {
        let tol = 0.5;
        assert!(clip_inside(Vec4::new(0.0, 0.0, 0.5, 1.0), tol));
        assert!(clip_inside(Vec4::new(1.49, -1.49, 0.5, 1.0), tol));
        assert!(!clip_inside(Vec4::new(1.51, 0.0, 0.5, 1.0), tol));
        assert!(!clip_inside(Vec4::new(0.0, -1.51, 0.5, 1.0), tol));
        // Depth: behind the near plane or past the far plane.
        assert!(!clip_inside(Vec4::new(0.0, 0.0, -0.01, 1.0), tol));
        assert!(!clip_inside(Vec4::new(0.0, 0.0, 1.01, 1.0), tol));
    }

    #[test]
    fn frustum_keeps_a_blade_with_any_of_its_three_points_inside() {
        let b = blade();
        // Orthographic-like clip: identity maps world = clip with w = 1.
        let shift = |x: f32| Mat4::from_translation(Vec3::new(x, 0.0, 0.5));
        // The root and tip are at y = 0 and 2 → tip (y = 2) is outside, root inside.
        assert!(!cull_frustum(&b, shift(0.0), 0.0));
        // Moved far to the side: all three outside.
        assert!(cull_frustum(&b, shift(3.0), 0.5));
        // Just inside thanks to the tolerance.
        assert!(!cull_frustum(&b, shift(1.4), 0.5));
        assert!(cull_frustum(&b, shift(1.6), 0.5));
    }

    #[test]
    fn distance_buckets_thin_the_far_field() {
        let b = blade();
        let cam = |d: f32| Vec3::new(d, 5.0, 0.0);
        // Near the camera every bucket is kept.
        for id in 0..10 {
            assert!(!cull_distance(&b, id, cam(0.0), 100.0, 10));
        }
        // At 55 % of dmax: floor(10·0.45) = 4 → buckets 0..=4 kept, 5..=9 culled.
        for id in 0..10 {
            assert_eq!(
                cull_distance(&b, id, cam(55.0), 100.0, 10),
                id % 10 > 4,
                "id {id}"
            );
        }
        // Beyond dmax everything goes; the height of the camera does not count.
        assert!(cull_distance(&b, 0, cam(100.5), 100.0, 10));
        assert!(!cull_distance(
            &b,
            0,
            Vec3::new(99.5, 500.0, 0.0),
            100.0,
            10
        ));
    }

    #[test]
    fn enabled_mask_switches_tests() {
        let b = blade();
        let far = Vec3::new(1000.0, 0.0, 0.0);
        let mut p = CullParams {
            orientation_threshold: 0.9,
            frustum_tolerance: 0.5,
            max_distance: 100.0,
            buckets: 10,
            enabled: DISTANCE,
            ..Default::default()
        };
        assert!(!is_visible(&b, 0, far, Mat4::IDENTITY, &p));
        p.enabled = 0;
        assert!(is_visible(&b, 0, far, Mat4::IDENTITY, &p));
    }

    #[test]
    fn outcome_names_the_first_test_that_removes() {
        let b = blade();
        // Far along the width axis: edge-on, outside the identity "frustum" and
        // beyond dmax, so every test would remove it.
        let camera = Vec3::new(-1000.0, 0.0, 0.0);
        let view_proj = Mat4::from_translation(Vec3::new(50.0, 0.0, 0.5));
        let mut p = CullParams {
            orientation_threshold: 0.9,
            frustum_tolerance: 0.5,
            max_distance: 100.0,
            buckets: 10,
            enabled: ALL,
            ..Default::default()
        };
        let outcome =
            |p: &CullParams| cull_outcome(&b, 0, camera, view_proj, p, &[], &HiZLayout::default());
        assert_eq!(outcome(&p), BY_ORIENTATION);
        p.enabled &= !ORIENTATION;
        assert_eq!(outcome(&p), BY_FRUSTUM);
        p.enabled &= !FRUSTUM;
        assert_eq!(outcome(&p), BY_DISTANCE);
        p.enabled &= !DISTANCE;
        // No pyramid: occlusion keeps it.
        assert_eq!(outcome(&p), KEPT);
    }
}
