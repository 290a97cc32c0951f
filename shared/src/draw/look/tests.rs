//! Unit tests of the natural look.

use super::clump::*;
use super::coverage::*;
use super::leaf::*;
use super::shadow::*;
use super::sky::*;
use super::*;
use crate::Blade;
use crate::cull::blade::{cull_distance, cull_orientation, orientation_alignment};

#[test]
fn clumps_are_seeded_continuous_and_varied() {
    let p = Vec3::new(3.3, 0.0, -7.1);
    assert_eq!(clump_at(p, 1.6, 5), clump_at(p, 1.6, 5));
    assert_ne!(clump_at(p, 1.6, 5), clump_at(p, 1.6, 6));
    // Along a line 40 units long in steps of 1/400 of a clump, no value jumps:
    // the blend is continuous (a hard Voronoi border would jump by up to 0.55).
    let (mut lo, mut hi) = (f32::MAX, f32::MIN);
    let mut last = clump_at(Vec3::ZERO, 1.6, 5);
    let step = 1.6 / 400.0;
    for i in 1..(40.0 / step) as i32 {
        let c = clump_at(
            Vec3::new(i as f32 * step, 0.0, 0.3 * i as f32 * step),
            1.6,
            5,
        );
        assert!((c.height - last.height).abs() < 0.02, "height jumps at {i}");
        assert!(
            (c.dryness - last.dryness).abs() < 0.03,
            "dryness jumps at {i}"
        );
        assert!((c.lean - last.lean).length() < 0.02, "lean jumps at {i}");
        (lo, hi) = (lo.min(c.height), hi.max(c.height));
        last = c;
    }
    // Yet clumps differ: the height factor spans much of its range.
    assert!(hi - lo > 0.3, "{lo}..{hi}");
}

#[test]
fn a_clump_packs_into_one_vec4() {
    let c = clump_at(Vec3::new(1.0, 0.0, 2.0), 1.6, 3);
    let back = Clump::unpack(c.pack());
    assert_eq!((back.lean.x, back.lean.z), (c.lean.x, c.lean.z));
    assert_eq!(
        (back.height, back.dryness, back.lean.y),
        (c.height, c.dryness, 0.0)
    );
}

#[test]
fn a_dressed_blade_keeps_its_root_and_leans_sideways() {
    let b = Blade::at_rest(Vec3::new(1.0, 0.0, 2.0), Vec3::Y, 0.3, 2.0, 0.1, 9.0);
    let clump = Clump {
        lean: Vec3::new(0.3, 5.0, 0.0),
        height: 0.8,
        dryness: 0.5,
    };
    let d = dressed_blade(&b, &clump, 0.5, 0.5);
    assert_eq!(d.root(), b.root());
    // The up part of the lean is dropped; the tip moves towards +X; the length
    // v0→v2 is the height times the factor (0.8 · 1.0).
    assert!(d.tip().x > b.tip().x && (d.tip().z - b.tip().z).abs() < 1e-6);
    assert!(((d.tip() - d.root()).length() - 1.6).abs() < 1e-5);
    assert!((d.height() - 1.6).abs() < 1e-5);
    assert!((d.width() - 0.05).abs() < 1e-7);
    assert_eq!(d.stiffness(), b.stiffness());
}

#[test]
fn rounded_normals_are_unit_and_tilt_towards_each_edge() {
    let (n, t1) = (Vec3::Z, Vec3::X);
    assert!((rounded_normal(n, t1, 0.5) - n).length() < 1e-6);
    for u in [0.0, 0.2, 0.7, 1.0] {
        let r = rounded_normal(n, t1, u);
        assert!((r.length() - 1.0).abs() < 1e-5);
        assert_eq!(r.x > 0.0, u > 0.5, "u = {u}: {r}");
    }
    assert!((rounded_normal(n, t1, 1.0).x - ROUNDING.sin()).abs() < 1e-5);
}

#[test]
fn translucency_only_with_the_sun_behind() {
    let facing = Vec3::Z;
    let eye = Vec3::Z;
    // The sun on the viewer's side: nothing comes through.
    for l in [
        Vec3::Z,
        Vec3::new(0.6, 0.0, 0.8),
        Vec3::new(0.0, 0.99, 0.14),
    ] {
        assert_eq!(translucency(facing, l.normalize(), eye), 0.0);
    }
    // Behind the blade: light through it, most when looking into the sun.
    let side = translucency(facing, Vec3::new(0.8, 0.0, -0.6), eye);
    let into = translucency(facing, -Vec3::Z, eye);
    assert!(side > 0.0 && into > side, "{side} {into}");
    assert_eq!(soft_specular(facing, -Vec3::Z, eye), 0.0);
    assert!(soft_specular(facing, Vec3::Z, eye) > 0.09);
}

#[test]
fn occlusion_grows_towards_the_root_and_with_density() {
    assert_eq!(ambient_occlusion(1.0, 1.0), 1.0);
    assert!((ambient_occlusion(0.0, 1.0) - 0.25).abs() < 1e-6);
    let mut last = 0.0;
    for i in 0..=10 {
        let ao = ambient_occlusion(i as f32 / 10.0, 1.0);
        assert!(ao > last);
        last = ao;
    }
    assert!(ambient_occlusion(0.2, 0.3) > ambient_occlusion(0.2, 1.0));
    assert_eq!(ambient_occlusion(0.0, 0.0), 1.0);
}

#[test]
fn tone_map_is_monotonic_from_zero() {
    assert_eq!(aces(0.0), 0.0);
    assert_eq!(tone_map(Vec3::ZERO, 3.0), Vec3::ZERO);
    let mut last = 0.0;
    for i in 1..2000 {
        let y = aces(i as f32 * 0.01);
        assert!(y >= last && y <= 1.0);
        last = y;
    }
    assert!(last > 0.99);
    // Mid grey stays mid: 0.18 maps near 0.27 (display linear).
    assert!((aces(0.18) - 0.267).abs() < 0.01, "{}", aces(0.18));
    assert!(tone_map(Vec3::splat(0.1), 2.0).x > tone_map(Vec3::splat(0.1), 1.0).x);
}

#[test]
fn fades_reach_zero_where_the_tests_remove_the_blade() {
    // Distance: walk the blade outwards; the width falls to 0 no later than the
    // test removes it, and is 1 well inside.
    let (dmax, n) = (40.0, 8);
    for id in 0..16 {
        let mut removed_at = None;
        for step in 0..4100 {
            let d = step as f32 * 0.01;
            let b = Blade::at_rest(Vec3::new(d, 0.0, 0.0), Vec3::Y, 0.0, 2.0, 0.1, 9.0);
            if cull_distance(&b, id, Vec3::ZERO, dmax, n) {
                removed_at.get_or_insert(d);
            } else {
                let fade = distance_fade(d, dmax, n, id);
                // 0.01 units before the cut, the blade is thinner than 1/50.
                assert!((0.0..=1.0).contains(&fade));
                if cull_distance(
                    &Blade::at_rest(Vec3::new(d + 0.01, 0.0, 0.0), Vec3::Y, 0.0, 2.0, 0.1, 9.0),
                    id,
                    Vec3::ZERO,
                    dmax,
                    n,
                ) {
                    assert!(fade < 0.02, "id {id} at {d}: {fade}");
                }
            }
        }
        assert!(removed_at.is_some());
    }
    assert_eq!(distance_fade(0.0, dmax, n, 7), 1.0);
    // Whole until the last quarter of its bucket: bucket 7 is removed where
    // 8·(1 − d/40) < 7, d > 5; at d = 3.5 the position is 7.3.
    assert_eq!(distance_fade(3.5, dmax, n, 7), 1.0);
    assert!((distance_fade(4.5, dmax, n, 7) - 0.4).abs() < 1e-4);
    // Orientation: 0 at the threshold, 1 a band below.
    assert_eq!(orientation_fade(0.9, 0.9), 0.0);
    assert!(orientation_fade(0.9 - ORIENTATION_BAND, 0.9) > 0.9999);
    assert_eq!(orientation_fade(0.5, 0.9), 1.0);
    let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 9.0);
    let camera = Vec3::new(-10.0, 2.0, 0.5);
    let a = orientation_alignment(&b, camera);
    let paper = crate::cull::blade::CullParams {
        orientation_threshold: 0.9,
        ..Default::default()
    };
    assert!(cull_orientation(&b, camera, &paper) && orientation_fade(a, 0.9) == 0.0);
    assert_eq!(kept_share(0.0, dmax, n), 1.0);
    assert!(kept_share(35.0, dmax, n) < 0.3);
}

#[test]
fn coverage_masks_hold_alpha_on_average() {
    for samples in [1u32, 2, 4, 8] {
        assert_eq!(coverage_mask(1.0, samples, 0.3), (1 << samples) - 1);
        assert_eq!(coverage_mask(0.0, samples, 0.0), 0);
        for alpha in [0.1f32, 0.35, 0.5, 0.8] {
            let n = 1000;
            let bits: u32 = (0..n)
                .map(|i| coverage_mask(alpha, samples, (i as f32 + 0.5) / n as f32))
                .map(|m| {
                    assert!(m < (1 << samples));
                    m.count_ones()
                })
                .sum();
            let mean = bits as f32 / (n * samples) as f32;
            assert!((mean - alpha).abs() < 0.01, "{samples}x at {alpha}: {mean}");
        }
    }
}

#[test]
fn coverage_and_density_share_a_varying() {
    for mask in [0u32, 1, 5, 255] {
        for density in [0.0f32, 0.125, 0.5, 0.99] {
            let (m, d) = unpack_coverage(pack_coverage(mask, density, 3));
            assert_eq!(m, mask);
            assert!((d - density).abs() < 1e-4, "{mask} {density}: {d}");
        }
    }
}

#[test]
fn thin_blades_keep_their_coverage() {
    assert_eq!(thin_coverage(0.2, 0.1), (0.2, 1.0));
    let (w, alpha) = thin_coverage(0.025, 0.1);
    assert_eq!(w, 0.1);
    assert!((w * alpha - 0.025).abs() < 1e-7);
}

#[test]
fn the_sky_has_a_sun_and_fog_tends_to_it() {
    let sun = Vec3::new(0.3, 0.5, 0.8).normalize();
    let at_sun = sky(sun, sun);
    let away = sky(Vec3::new(-0.3, 0.5, -0.8).normalize(), sun);
    assert!(at_sun.x > 10.0 * away.x, "{at_sun} {away}");
    assert!((SUN_COS.0 - SUN_RADIUS.cos()).abs() < 1e-7);
    assert!((SUN_COS.1 - (1.2 * SUN_RADIUS).cos()).abs() < 1e-7);
    // Deeper blue overhead than at the horizon; darker below it.
    let zenith = sky(Vec3::Y, sun);
    let horizon = sky(Vec3::X, sun);
    assert!(zenith.z / zenith.x > horizon.z / horizon.x);
    assert!(sky(-Vec3::Y, sun).length() < horizon.length());
    let green = Vec3::new(0.1, 0.3, 0.05);
    assert_eq!(fog(green, 0.0, Vec3::X, sun, 0.01), green);
    let far = fog(green, 1e5, Vec3::X, sun, 0.01);
    assert!((far - fog_colour(Vec3::X, sun)).length() < 1e-4);
}

#[test]
fn the_sun_sees_the_scene_and_the_map_finds_shadows() {
    let to_sun = Vec3::new(0.4, 0.8, 0.3).normalize();
    let m = sun_view_proj(to_sun, Vec3::ZERO, 10.0);
    let c = shadow_coord(m, Vec3::ZERO);
    assert!((c - Vec3::new(0.5, 0.5, 0.5)).length() < 1e-5, "{c}");
    // Towards the sun is nearer to it (smaller depth); across stays in the map.
    assert!(shadow_coord(m, to_sun * 5.0).z < c.z);
    let across = shadow_coord(m, to_sun.cross(Vec3::Y).normalize() * 9.0);
    assert!(across.x > 0.0 && across.x < 1.0 && across.y > 0.0 && across.y < 1.0);
    let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 9.0);
    assert!(in_shadow_map(m, &b));
    let far = Blade::at_rest(Vec3::new(30.0, 0.0, 0.0), Vec3::Y, 0.0, 2.0, 0.1, 9.0);
    assert!(!in_shadow_map(m, &far));
    assert!(casts_shadow(m, &b, Vec3::new(3.0, 2.0, 0.0), 5.0));
    assert!(!casts_shadow(m, &b, Vec3::new(6.0, 2.0, 0.0), 5.0));
    // A map holding depth 0.4 everywhere shadows a point at depth 0.5 and lights
    // one at 0.3; outside the map is lit.
    let map = |_: i32, _: i32| 0.4;
    assert_eq!(shadow_factor(Vec3::new(0.5, 0.5, 0.5), 64, 0.001, map), 0.0);
    assert_eq!(shadow_factor(Vec3::new(0.5, 0.5, 0.3), 64, 0.001, map), 1.0);
    assert_eq!(shadow_factor(Vec3::new(1.5, 0.5, 0.5), 64, 0.001, map), 1.0);
    // Half the map occluded: a point on the edge is half lit.
    let half = |x: i32, _: i32| if x < 32 { 0.4 } else { 1.0 };
    let edge = shadow_factor(Vec3::new(0.5, 0.5, 0.5), 64, 0.001, half);
    assert!((edge - 0.5).abs() < 1e-5, "{edge}");
}

#[test]
fn palette_runs_fresh_to_dry_and_tips_are_drier() {
    assert_eq!(palette(0.0), FRESH);
    assert_eq!(palette(1.0), DRY);
    assert_eq!(palette(0.5), RIPE);
    let tint = palette(0.1);
    let (root, tip) = (blade_albedo(tint, 0.0), blade_albedo(tint, 1.0));
    assert!(root.length() < tip.length());
    // Redder (drier) relative to green at the tip.
    assert!(tip.x / tip.y > root.x / root.y);
}

#[test]
fn the_near_cascade_takes_what_it_holds_and_the_far_one_the_rest() {
    let to_sun = Vec3::new(0.3, 1.0, 0.2).normalize();
    let camera = Vec3::new(40.0, 2.0, -30.0);
    let far_sphere = (Vec3::new(40.0, 0.0, -30.0), 48.0);
    let near_cascade = near_sphere(far_sphere, camera);
    assert_eq!(near_cascade.1, NEAR_REACH);
    assert!((near_cascade.0 - camera).length() < NEAR_REACH / 16.0);
    let far = sun_view_proj(to_sun, far_sphere.0, far_sphere.1);
    let near = sun_view_proj(to_sun, near_cascade.0, near_cascade.1);
    let size = 1024;
    // Beside the camera: the left half, at the near map's own coordinate halved.
    let (on, c) = cascade_coord(near, far, camera, size);
    let own = shadow_coord(near, camera);
    assert!(on && c.x < 0.5);
    assert!((c.x - 0.5 * own.x).abs() < 1e-6 && (c.y - own.y).abs() < 1e-6);
    // Thirty units off: beyond the near cascade, in the right half.
    let off = camera + Vec3::new(30.0, 0.0, 0.0);
    let (on, c) = cascade_coord(near, far, off, size);
    assert!(on && c.x > 0.5);
    assert!((c.x - (0.5 + 0.5 * shadow_coord(far, off).x)).abs() < 1e-6);
    // Beyond both: on neither.
    assert!(!cascade_coord(near, far, camera + Vec3::new(200.0, 0.0, 0.0), size).0);
    // A small scene: one sphere for both.
    assert_eq!(near_sphere((Vec3::ZERO, 8.0), camera), (Vec3::ZERO, 8.0));
}

/// The casters' mesh grid covers every caster in whole workgroups of 32, none
/// wider than the grid's limit (hand-worked: 100 casters, 4 groups; 2^22, 131,072
/// groups as 32,768 x 4).
#[test]
fn caster_grid_covers_every_caster() {
    use spirv_std::glam::UVec3;
    assert_eq!(caster_grid(0), UVec3::new(0, 0, 1));
    assert_eq!(caster_grid(100), UVec3::new(4, 1, 1));
    assert_eq!(caster_grid(1 << 22), UVec3::new(32_768, 4, 1));
    for count in [1, 31, 32, 33, 1_000_001, 5_000_000] {
        let g = caster_grid(count);
        assert!(g.x * g.y * CASTERS_PER_GROUP >= count, "{count}: {g}");
        assert!((g.x * g.y - 1) * CASTERS_PER_GROUP < count + CASTERS_PER_GROUP * g.y);
        assert!(g.x <= crate::draw::meshlet::MESH_GRID_WIDTH);
    }
}
