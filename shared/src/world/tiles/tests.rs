//! Unit tests of the tiled world's blades.

use super::*;
use crate::blade::{HEIGHT, STIFFNESS, WIDTH};
use crate::cull::tile::*;

fn blades_of(tile: IVec2, camera: Vec3, params: &TileParams) -> Vec<(u32, Blade)> {
    (0..params.per_side * params.per_side)
        .map(|i| (i, tile_blade(tile, i, camera, params, &[])))
        .filter(|(_, b)| kept(b))
        .collect()
}

/// A camera above the origin (with `full_distance` far beyond the tiles near it,
/// every blade kept at its own width).
const NEAR: Vec3 = Vec3::new(0.0, 1.0, 0.0);

#[test]
fn a_tile_gives_the_same_blades_every_time_and_inside_it() {
    let params = TileParams {
        full_distance: 1e6,
        ..TileParams::default()
    };
    let tile = IVec2::new(-1, 1);
    let a = blades_of(tile, NEAR, &params);
    assert_eq!(a.len() as u32, params.per_side * params.per_side);
    assert_eq!(a, blades_of(tile, NEAR, &params));
    let other = blades_of(IVec2::new(-1, 2), NEAR, &params);
    assert_ne!(a[0].1, other[0].1, "another tile, other blades");
    let reseeded = TileParams { seed: 2, ..params };
    assert_ne!(a[0].1, blades_of(tile, NEAR, &reseeded)[0].1);
    for (_, b) in &a {
        let root = Vec2::new(b.root().x, b.root().z);
        assert_eq!(tile_of(root, &params), tile, "{root}");
        assert!((HEIGHT.0..HEIGHT.1).contains(&b.height()));
        assert!((WIDTH.0..WIDTH.1).contains(&b.width()));
        assert!((STIFFNESS.0..STIFFNESS.1).contains(&b.stiffness()));
    }
}

#[test]
fn neighbouring_tiles_meet_without_a_seam() {
    // 4 x 4 tiles; blades counted in strips a tenth of a tile wide: those across a
    // tile border hold as many as those inside a tile, within 6 % (a strip holds
    // about 1,640 blades). Planted fault (with 48 blades a side, when the strip held
    // about 920): cells laid over 48.5 rows instead of 48, leaving a sliver bare at
    // each border, gave 838 against 922 in the strip before it and failed.
    let params = TileParams {
        full_distance: 1e6,
        ..TileParams::default()
    };
    let tiles = 4;
    let strip = params.size / 10.0;
    let mut counts = vec![0u32; (tiles * 10) as usize];
    for tx in 0..tiles {
        for tz in 0..tiles {
            for (_, b) in blades_of(IVec2::new(tx, tz), NEAR, &params) {
                counts[(b.root().x / strip) as usize] += 1;
            }
        }
    }
    let mean = counts.iter().sum::<u32>() as f32 / counts.len() as f32;
    // Strips starting on a border, and the strips just before one.
    for (i, &c) in counts.iter().enumerate() {
        assert!(
            (c as f32 - mean).abs() < 0.06 * mean,
            "strip {i} (a border every 10): {c} blades against {mean}"
        );
    }
    // No two blades share a root, within a tile or across a border.
    let mut roots: Vec<(i64, i64)> = (0..tiles)
        .flat_map(|tx| (0..tiles).map(move |tz| IVec2::new(tx, tz)))
        .flat_map(|t| blades_of(t, NEAR, &params))
        .map(|(_, b)| ((b.root().x * 1e4) as i64, (b.root().z * 1e4) as i64))
        .collect();
    let n = roots.len();
    roots.sort_unstable();
    roots.dedup();
    assert_eq!(roots.len(), n);
}

/// Planted faults: a rank that changed with the distance (blades coming back
/// farther away) failed the nesting at 24 units; kept blades left at their own
/// width failed the coverage (243 against 276 at 16 units).
#[test]
fn blades_leave_with_distance_one_by_one_and_coverage_stays() {
    let params = TileParams::default();
    let tile = IVec2::new(0, 0);
    let centre = Vec3::new(4.0, 0.0, 4.0);
    let mut last: Option<Vec<u32>> = None;
    let all = (params.per_side * params.per_side) as f32;
    for step in 0..12 {
        // The camera receding from 8 to 96 units (the tile 8 units wide).
        let distance = 8.0 * (1.0 + step as f32);
        let camera = centre + Vec3::new(distance, 0.0, 0.0);
        let kept = blades_of(tile, camera, &params);
        let ids: Vec<u32> = kept.iter().map(|&(i, _)| i).collect();
        // Nested: every blade kept now was kept nearer.
        if let Some(nearer) = &last {
            assert!(ids.iter().all(|i| nearer.contains(i)), "at {distance}");
        }
        // The share kept, against the share asked at the tile's centre (the
        // roots span a tile, so the share varies across it).
        let share = kept_share(distance, &params);
        let measured = ids.len() as f32 / all;
        assert!(
            (measured - share).abs() < 0.15 * share + 0.01,
            "at {distance}: {measured} kept against {share}"
        );
        // Coverage: the kept blades' widths add up to what all blades' would,
        // while the widening is below its cap (share above 1 / MAX_WIDENING).
        if share > 1.2 / MAX_WIDENING {
            let width: f32 = kept.iter().map(|(_, b)| b.width()).sum();
            let full = all * 0.5 * (WIDTH.0 + WIDTH.1);
            assert!(
                (width - full).abs() < 0.12 * full,
                "at {distance}: width {width} against {full}"
            );
        }
        last = Some(ids);
    }
    assert!(
        last.unwrap().len() < (all * 0.05) as usize,
        "few left far away"
    );
}

#[test]
fn on_the_valley_blades_stand_on_its_surface_and_not_on_the_path() {
    let params = TileParams {
        terrain: TERRAIN_VALLEY,
        full_distance: 1e6,
        ..TileParams::default()
    };
    // The tiles across the path at z = 100 (its centre line at x = 31.9).
    let z = 100.0f32;
    let x = 60.0 * (z / 180.0).sin();
    let row = tile_of(Vec2::new(x, z), &params).y;
    let (mut on_path, mut kept_blades) = (0, 0);
    for tx in -2..=2 {
        let tile = IVec2::new(tile_of(Vec2::new(x, z), &params).x + tx, row);
        for i in 0..params.per_side * params.per_side {
            let b = tile_blade(tile, i, NEAR, &params, &[]);
            let p = Vec2::new(b.root().x, b.root().z);
            if terrain::bare(p) {
                on_path += 1;
                assert!(!kept(&b), "a blade on the path at {p}");
                continue;
            }
            assert!(kept(&b));
            kept_blades += 1;
            assert!((b.root().y - terrain::valley_height(p)).abs() < 1e-4);
            assert!((b.up_dir() - terrain::valley_normal(p)).length() < 1e-5);
            // At rest along its ground's normal.
            let along = (b.tip() - b.root()).normalize();
            assert!((along - b.up_dir()).length() < 1e-4);
        }
    }
    // The path (5 m wide) crosses the 40 m of tiles: about an eighth of the blades.
    let share = on_path as f32 / (on_path + kept_blades) as f32;
    assert!((0.09..0.16).contains(&share), "{share} on the path");
}

/// Planted faults: the box without the blades' height (a tile whose ground is
/// below the view but whose tips are in it, with the camera looking up) failed,
/// and so did a right plane at half the view's width.
#[test]
fn the_tiles_in_view_are_those_a_blade_of_could_be_seen_in() {
    use spirv_std::glam::camera::rh;
    let params = TileParams::default();
    let eye = Vec3::new(0.0, 1.7, 0.0);
    let view_proj = |look: Vec3| {
        let view = rh::view::look_at_mat4(eye, look, Vec3::Y);
        rh::proj::vulkan::perspective(1.0, 16.0 / 9.0, 0.1, 2000.0) * view
    };
    let down = view_proj(Vec3::new(0.0, 1.0, -20.0));
    let seen = |t: IVec2| tile_in_view(t, down, eye, &params, (0.0, 0.0), 300.0);
    // Ahead (−z), beside the camera, behind it, out of reach.
    assert!(seen(IVec2::new(0, -3)) && seen(IVec2::new(-1, -1)) && seen(IVec2::new(0, -1)));
    assert!(!seen(IVec2::new(0, 3)), "behind");
    assert!(!seen(IVec2::new(0, -60)), "beyond the reach");
    assert!(!seen(IVec2::new(30, -3)), "far to the side");
    // Against blades: every blade of a tile out of view is outside the view volume
    // (root and tip), over every tile within reach; and most tiles in view hold a
    // blade inside it. Looking a little down, and up (the near ground out of view,
    // the near tips in it).
    let every = TileParams {
        full_distance: 1e6,
        ..params
    };
    for look in [Vec3::new(0.0, 1.0, -20.0), Vec3::new(0.0, 6.0, -20.0)] {
        let view_proj = view_proj(look);
        let (mut in_view, mut with_blade) = (0, 0);
        for tx in -40..40 {
            for tz in -40..40 {
                let tile = IVec2::new(tx, tz);
                let visible = tile_in_view(tile, view_proj, eye, &params, (0.0, 0.0), 300.0);
                let mut any = false;
                for i in (0..params.per_side * params.per_side).step_by(7) {
                    let b = tile_blade(tile, i, eye, &every, &[]);
                    for p in [b.root(), b.tip()] {
                        let c = view_proj * p.extend(1.0);
                        let inside = c.w > 0.0
                            && c.x.abs() <= c.w
                            && c.y.abs() <= c.w
                            && (0.0..=c.w).contains(&c.z)
                            && (p - eye).length() <= 300.0;
                        assert!(visible || !inside, "tile {tile} culled with {p} in view");
                        any |= inside;
                    }
                }
                in_view += u32::from(visible);
                with_blade += u32::from(visible && any);
            }
        }
        assert!(
            with_blade * 10 >= in_view * 9,
            "{with_blade} of {in_view} tiles in view hold a blade in it"
        );
    }
}

/// Planted fault: cells in plain row order (index % n, index / n) put the first
/// 64 blades in one row and failed the first prefix.
#[test]
fn every_prefix_of_the_blades_spreads_over_the_tile() {
    let n = 64;
    // Every cell taken once.
    let mut seen = vec![false; (n * n) as usize];
    for i in 0..n * n {
        let c = cell_of(i, n);
        assert!(c.x < n && c.y < n);
        assert!(!seen[(c.y * n + c.x) as usize], "cell {c} twice");
        seen[(c.y * n + c.x) as usize] = true;
    }
    // The first 4^j blades: one in each 2^j x 2^j block.
    for j in 1..=5u32 {
        let blocks = 1u32 << j;
        let mut hit = vec![0u32; (blocks * blocks) as usize];
        for i in 0..blocks * blocks {
            let c = cell_of(i, n) / (n / blocks);
            hit[(c.y * blocks + c.x) as usize] += 1;
        }
        assert!(hit.iter().all(|&h| h == 1), "prefix {}", blocks * blocks);
    }
}

/// Planted fault: a count from the share at the tile's centre rather than its
/// nearest point left kept blades out and failed.
#[test]
fn a_far_tile_keeps_none_of_the_blades_past_its_count() {
    let params = TileParams::default();
    let all = params.per_side * params.per_side;
    let tile = IVec2::new(2, -1);
    for distance in [0.0, 12.0, 20.0, 40.0, 90.0, 400.0] {
        let camera = Vec3::new(-distance, 1.7, -3.0);
        let count = far_count(tile, camera, &params, (0.0, 0.0), &[]);
        let last_kept = (0..all)
            .filter(|&i| kept(&tile_blade(tile, i, camera, &params, &[])))
            .max()
            .map_or(0, |i| i + 1);
        assert!(last_kept <= count, "at {distance}: {last_kept} > {count}");
        // And not many more than that: within a row's worth of the tile.
        assert!(
            count <= last_kept + all / 8,
            "at {distance}: {count} for {last_kept}"
        );
    }
    assert_eq!(
        far_count(tile, Vec3::new(20.0, 1.0, -5.0), &params, (0.0, 0.0), &[]),
        all
    );
}

/// A wall 3.2 units high across the view 8 units ahead of an eye 4 units up hides
/// the tiles (2 units wide) just behind it, and not those before it, nor those
/// far enough behind for their blades' tips to rise above its top edge (the
/// occluders' depth built by `hiz::build` from the wall drawn by hand). Planted
/// fault: the box without the blades' height hid the far tile and failed.
#[test]
fn a_tile_behind_a_wall_is_hidden_and_one_before_it_is_not() {
    use spirv_std::glam::camera::rh;
    let params = TileParams {
        size: 2.0,
        per_side: 16,
        ..TileParams::default()
    };
    let eye = Vec3::new(0.5, 4.0, 0.0);
    let view = rh::view::look_at_mat4(eye, Vec3::new(0.5, 2.0, -10.0), Vec3::Y);
    let view_proj = rh::proj::vulkan::perspective(1.2, 1.0, 0.1, 500.0) * view;
    let (w, h) = (512u32, 512u32);
    // The wall: the plane z = −8 from y = 0 to 3.2, x = −40 to 40, its depth per
    // pixel where the ray meets it, else the far plane.
    let clip_to_world = view_proj.inverse();
    let mut depth = vec![1.0f32; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let ndc = Vec2::new(
                (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
                (y as f32 + 0.5) / h as f32 * 2.0 - 1.0,
            );
            let near = clip_to_world.project_point3(ndc.extend(0.0));
            let far = clip_to_world.project_point3(ndc.extend(1.0));
            let t = (-8.0 - near.z) / (far.z - near.z);
            let p = near + (far - near) * t;
            if (0.0..=1.0).contains(&t) && (0.0..=3.2).contains(&p.y) && p.x.abs() < 40.0 {
                let c = view_proj * p.extend(1.0);
                depth[(y * w + x) as usize] = c.z / c.w;
            }
        }
    }
    let (hiz, pyramid) = crate::cull::hiz::build(&depth, w, h);
    let hidden = |t: IVec2| {
        let span = tile_box(t, &params, (0.0, 0.0), &[]);
        tile_occluded(t, &params, span, view_proj, &pyramid, &hiz)
    };
    // Just behind the wall (z from −12 to −10): tips at least 8.5° below the eye,
    // the wall's top 5.7° below it.
    assert!(hidden(IVec2::new(0, -6)) && hidden(IVec2::new(-1, -6)));
    // Before it.
    assert!(!hidden(IVec2::new(0, -2)) && !hidden(IVec2::new(0, -4)));
    // 24 to 26 units away: the ground hidden (8.7° below the eye), the tips not
    // (3.6° below).
    assert!(!hidden(IVec2::new(0, -13)), "tips above the wall's edge");
}

/// Planted fault: a quarter of the slope bound left roots outside the range and
/// failed (half of it did not: over these 200 tiles the bound is not tight).
#[test]
fn a_valley_tile_s_ground_range_holds_its_blades() {
    let params = TileParams {
        terrain: TERRAIN_VALLEY,
        full_distance: 1e6,
        ..TileParams::default()
    };
    for t in 0..200 {
        let tile = IVec2::new((t * 37) % 180 - 90, (t * 53) % 180 - 90);
        let (lo, hi) = tile_ground(tile, &params, (-1e3, 1e3), &[]);
        for i in (0..params.per_side * params.per_side).step_by(13) {
            let y = root_of(tile, i, &params);
            let h = terrain::valley_height(y);
            assert!((lo..=hi).contains(&h), "{tile}: {h} outside {lo}..{hi}");
        }
    }
}

#[test]
fn a_leaving_blade_thins_to_nothing() {
    // Just kept: a sliver; well inside its share: the full widening.
    assert!(width_scale(0.499, 0.5) < 0.05);
    assert_eq!(width_scale(0.5, 0.5), 0.0);
    assert_eq!(width_scale(0.1, 0.5), 2.0);
    assert_eq!(width_scale(0.0, 0.1), MAX_WIDENING);
    // Near the camera every blade at its own width; just past full_distance the
    // last ranks start to thin.
    assert_eq!(width_scale(0.999, 1.0 / (1.0 - FADE) + 1e-3), 1.0);
    assert!(width_scale(0.95, 1.0) < 1.0);
    // Continuous in the share: no jump as the camera moves (the steepest slope,
    // at the start of the fade, is MAX_WIDENING / (FADE · share) = 133 here).
    let mut previous = width_scale(0.3, 0.3);
    for i in 1..=2000 {
        let share = 0.3 + 0.0001 * i as f32;
        let scale = width_scale(0.3, share);
        assert!(
            (scale - previous).abs() < 0.02,
            "{share}: {previous} to {scale}"
        );
        previous = scale;
    }
}
