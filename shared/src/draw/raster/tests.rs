//! Unit tests of `raster`.

use super::*;
use spirv_std::glam::Vec3;

#[test]
fn packing_orders_by_depth_and_round_trips() {
    let a = pack(0.25, 7, 0.5);
    let b = pack(0.5, 3, 0.0);
    assert!(a < b, "nearer is smaller");
    let (depth, slot, v) = unpack(a);
    assert_eq!((depth, slot), (0.25, 7));
    assert!((v - 0.5).abs() <= 0.5 / 255.0 + 1e-6, "{v}");
    // The largest slot and the ends of the blade survive.
    let (_, slot, v) = unpack(pack(1.0, (1 << SLOT_BITS) - 1, 1.0));
    assert_eq!((slot, v), ((1 << SLOT_BITS) - 1, 1.0));
    assert!(pack(1.0, (1 << SLOT_BITS) - 1, 1.0) < EMPTY);
    assert_eq!(unpack(pack(0.75, 0, 0.0)).2, 0.0);
}

#[test]
fn the_two_words_read_as_the_value() {
    // A buffer of u32 holds the low word first (little-endian), as the shading reads it.
    let words = |value: u64| (value as u32, (value >> 32) as u32);
    for (depth, slot, v) in [
        (0.25, 7, 0.5),
        (1.0, (1 << SLOT_BITS) - 1, 1.0),
        (0.0, 0, 0.0),
    ] {
        let (low, high) = words(pack(depth, slot, v));
        assert_eq!(unpack_words(low, high), Some(unpack(pack(depth, slot, v))));
    }
    let (low, high) = words(EMPTY);
    assert_eq!(unpack_words(low, high), None);
    // The far plane at the largest slot and v is still a blade, not the empty value.
    let (low, high) = words(pack(1.0, (1 << SLOT_BITS) - 1, 1.0));
    assert!(unpack_words(low, high).is_some());
}

#[test]
fn thin_blades_keep_their_expected_coverage() {
    // Over many blades a quarter-pixel blade is drawn about a quarter of the time,
    // and the same blade always alike.
    let drawn = (0..10_000).filter(|&i| covers(0.25, i)).count();
    assert!((2_300..2_700).contains(&drawn), "{drawn}");
    assert!((0..100).all(|i| covers(1.0, i) && covers(3.0, i)));
    assert_eq!(covers(0.25, 42), covers(0.25, 42));
    assert!((0..100).all(|i| !covers(0.0, i)));
}

/// A square target `size` pixels wide with threshold `below` and `segments`, and
/// a camera 10 units in front of the origin at height 1 looking down −z (1 radian
/// of view): (params, eye, view-projection, focal length in pixels).
fn looking_at_the_origin(size: u32, below: f32, segments: u32) -> (RasterParams, Vec3, Mat4, f32) {
    use spirv_std::glam::camera::rh;
    let params = RasterParams {
        width: size,
        height: size,
        below,
        segments,
    };
    let eye = Vec3::new(0.0, 1.0, 10.0);
    let view = rh::view::look_at_mat4(eye, Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
    let view_proj = rh::proj::vulkan::perspective(1.0, 1.0, 0.1, 100.0) * view;
    (
        params,
        eye,
        view_proj,
        crate::cull::lod::focal_pixels(1.0, size as f32),
    )
}

#[test]
fn a_blade_is_drawn_as_its_curve_a_pixel_wide() {
    // An upright blade 2 units tall 10 units ahead, seen by a camera looking down
    // -z: its curve is a vertical run of pixels from the root to the tip.
    let (params, camera, view_proj, focal) = looking_at_the_origin(64, 16.0, 2);
    // Wide enough to be drawn whatever the hash says (1.2 pixels), narrow enough
    // to be drawn as a line.
    let blade = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.2, 10.0);
    let mut pixels = Vec::new();
    let quad = (crate::draw::shape::SHAPE_QUAD, 0.5);
    let coverage = Coverage::of(&blade, 9, quad, camera, focal);
    let n = raster_blade(&blade, 5, &coverage, view_proj, &params, |x, y, packed| {
        pixels.push((x, y, packed))
    });
    assert_eq!(n as usize, pixels.len());
    // About its height on screen in pixels, in one column at the centre.
    let tall = screen_height(2.0, 10.0, focal);
    assert!((n as f32 - tall).abs() <= 3.0, "{n} pixels for {tall}");
    assert!(
        pixels.iter().all(|&(x, _, _)| x == 31 || x == 32),
        "{pixels:?}"
    );
    // The slot, and v from the root (0) to the tip (1) along the run.
    let vs: Vec<f32> = pixels.iter().map(|&(_, _, p)| unpack(p).2).collect();
    assert!(pixels.iter().all(|&(_, _, p)| unpack(p).1 == 5));
    assert_eq!(vs.first(), Some(&0.0));
    assert_eq!(vs.last(), Some(&1.0));
    assert!(vs.windows(2).all(|w| w[1] >= w[0]), "{vs:?}");
    // Behind the camera: nothing.
    let behind = Blade::at_rest(Vec3::new(0.0, 0.0, 20.0), Vec3::Y, 0.0, 2.0, 2.0, 10.0);
    assert_eq!(
        raster_blade(&behind, 0, &coverage, view_proj, &params, |_, _, _| {}),
        0
    );
}

#[test]
fn a_wide_blade_is_drawn_as_its_surface() {
    // An upright blade 2 units tall and 1 wide, 10 units ahead, facing the camera:
    // about 23.4 by 11.7 pixels, a quad, or a triangle of half its area.
    let (params, eye, view_proj, focal) = looking_at_the_origin(128, 100.0, 3);
    // Facing +z: its width along x.
    let blade = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 1.0, 10.0);
    assert!(blade.width_dir().x.abs() > 0.99, "{:?}", blade.width_dir());
    let (tall, wide) = (
        screen_height(2.0, 10.0, focal),
        screen_height(1.0, 10.0, focal),
    );
    let draw = |shape| {
        let coverage = Coverage::of(&blade, 4, (shape, 0.5), eye, focal);
        assert!(coverage.width_px >= WIDE_PX);
        let mut pixels = std::collections::BTreeMap::new();
        let n = raster_blade(&blade, 2, &coverage, view_proj, &params, |x, y, p| {
            // Within a quad each pixel once; a row shared by two quads twice at most.
            let seen = pixels.entry((x, y)).or_insert((p, 0));
            seen.0 = seen.0.min(p);
            seen.1 += 1;
        });
        assert!(pixels.values().all(|&(_, times)| times <= 2), "{pixels:?}");
        assert!(n as usize >= pixels.len());
        pixels
    };
    let quad = draw(crate::draw::shape::SHAPE_QUAD);
    let area = tall * wide;
    let covered = quad.len() as f32;
    assert!(
        (covered - area).abs() < 0.1 * area,
        "{covered} pixels for {area}"
    );
    // Centred on column 64, as wide as the blade.
    let xs: Vec<u32> = quad.keys().map(|&(x, _)| x).collect();
    let (x_min, x_max) = (*xs.iter().min().unwrap(), *xs.iter().max().unwrap());
    assert!(
        ((x_max - x_min + 1) as f32 - wide).abs() <= 1.0,
        "{x_min}..{x_max}"
    );
    assert!((x_min + x_max) / 2 == 63 || (x_min + x_max) / 2 == 64);
    // v from the root (the bottom row: Vulkan's y points down) to the tip.
    let v_at = |y: u32| {
        quad.iter()
            .filter(|((_, row), _)| *row == y)
            .map(|(_, &(p, _))| unpack(p).2)
            .fold(0.0f32, f32::max)
    };
    let ys: Vec<u32> = quad.keys().map(|&(_, y)| y).collect();
    let (y_min, y_max) = (*ys.iter().min().unwrap(), *ys.iter().max().unwrap());
    assert!(
        v_at(y_max) < 0.15 && v_at(y_min) > 0.85,
        "{} {}",
        v_at(y_max),
        v_at(y_min)
    );
    assert!(quad.values().all(|&(p, _)| unpack(p).1 == 2));
    // Lanes sharing the blade plot the same pixels, each once.
    let coverage = Coverage::of(&blade, 4, (crate::draw::shape::SHAPE_QUAD, 0.5), eye, focal);
    let mut shared = std::collections::BTreeMap::new();
    let mut total = 0;
    for lane in 0..9 {
        total += raster_wide(
            &blade,
            2,
            &coverage,
            view_proj,
            &params,
            (lane, 3),
            |x, y, p| {
                let seen = shared.entry((x, y)).or_insert(p);
                *seen = (*seen).min(p);
            },
        );
    }
    let alone = raster_blade(&blade, 2, &coverage, view_proj, &params, |_, _, _| {});
    assert_eq!(total, alone);
    assert!(
        shared.iter().eq(quad
            .iter()
            .map(|(&k, &(p, _))| (k, p))
            .collect::<std::collections::BTreeMap<_, _>>()
            .iter())
    );
    // A triangle blade closes at its tip. At rest its v runs unevenly up the blade
    // (h = 2v − v², the guide on the tip), so its outline is a parabola, not a
    // triangle: about two thirds of the quad. Its strip of 3 quads is a polygon
    // whose area (the shoelace formula over its edges) the pixels match.
    let triangle = draw(crate::draw::shape::SHAPE_TRIANGLE).len() as f32;
    let coverage = Coverage::of(
        &blade,
        4,
        (crate::draw::shape::SHAPE_TRIANGLE, 0.5),
        eye,
        focal,
    );
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for i in 0..=3 {
        let (l, r, _) =
            edges_on_screen(&blade, i as f32 / 3.0, &coverage, view_proj, &params).unwrap();
        left.push((l.x, l.y));
        right.push((r.x, r.y));
    }
    let outline: Vec<(f32, f32)> = left.into_iter().chain(right.into_iter().rev()).collect();
    let polygon = 0.5
        * (0..outline.len())
            .map(|i| {
                let (a, b) = (outline[i], outline[(i + 1) % outline.len()]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum::<f32>()
            .abs();
    assert!(
        (polygon / area - 0.648).abs() < 0.01,
        "the strip's area {polygon} against the quad's {area}"
    );
    assert!(
        (triangle - polygon).abs() < 0.1 * polygon,
        "{triangle} pixels for {polygon}"
    );
}

#[test]
fn a_tapering_blade_covers_less_towards_its_tip() {
    // A triangle blade half a pixel wide at the root: about half of its root's
    // steps are drawn, and none at the tip, where it closes.
    let c = Coverage {
        width_px: 0.5,
        shape: crate::draw::shape::SHAPE_TRIANGLE,
        tip_start: 0.5,
        index: 3,
        height_px: 8.0,
    };
    let root = (0..4000).filter(|&s| c.draws(0.0, s)).count();
    let middle = (0..4000).filter(|&s| c.draws(0.5, s)).count();
    assert!((1_800..2_200).contains(&root), "{root}");
    assert!((800..1_200).contains(&middle), "{middle}");
    assert_eq!((0..4000).filter(|&s| c.draws(1.0, s)).count(), 0);
    // A quad blade wider than a pixel draws every step.
    let wide = Coverage {
        width_px: 1.5,
        shape: crate::draw::shape::SHAPE_QUAD,
        ..c
    };
    assert!((0..100).all(|s| wide.draws(0.9, s)));
}

#[test]
fn the_dispatch_covers_every_far_blade() {
    assert_eq!(raster_dispatch(0, 64, 32_768), (0, 1));
    assert_eq!(raster_dispatch(1, 64, 32_768), (1, 1));
    assert_eq!(raster_dispatch(65, 64, 32_768), (2, 1));
    let (x, y) = raster_dispatch(16_777_216, 64, 32_768);
    assert!(x <= 32_768 && x * y * 64 >= 16_777_216 && (x * (y - 1)) * 64 < 16_777_216);
}

#[test]
fn the_preparation_covers_every_pixel_only_with_far_blades() {
    assert_eq!(prepare_dispatch(0, (1920, 1080), 8), (0, 1));
    assert_eq!(prepare_dispatch(1, (1920, 1080), 8), (240, 135));
    assert_eq!(prepare_dispatch(5, (13, 9), 8), (2, 2));
}

#[test]
fn far_means_shorter_on_screen_than_the_threshold() {
    let blade = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 1.0, 0.1, 10.0);
    let params = |below| RasterParams {
        below,
        ..Default::default()
    };
    // 1 unit at 10 units with a focal length of 100 pixels: 10 pixels tall.
    let camera = Vec3::new(0.0, 0.0, 10.0);
    assert!(is_far(&blade, camera, 100.0, &params(12.0)));
    assert!(!is_far(&blade, camera, 100.0, &params(8.0)));
    assert!(
        !is_far(&blade, camera, 100.0, &params(0.0)),
        "0 turns it off"
    );
}

/// A segment from far off the target onto it: only the samples that may be on it are
/// stepped (at most its width and two more, against the 5,040 of its length), and
/// they plot the pixels stepping every sample plots. Planted fault: every sample
/// kept (`samples_on_target` giving 0 to `samples`) fails the count.
#[test]
fn a_segment_far_off_the_target_costs_its_pixels_on_it() {
    let params = RasterParams {
        width: 64,
        height: 64,
        below: 16.0,
        segments: 1,
    };
    let point = |x: f32, y: f32, depth: f32, v: f32| ScreenPoint { x, y, depth, v };
    let inside = |p: &ScreenPoint| {
        p.x >= 0.0 && p.y >= 0.0 && p.x < 64.0 && p.y < 64.0 && p.depth >= 0.0 && p.depth <= 1.0
    };
    let along = |from: ScreenPoint, to: ScreenPoint, i: u32, n: u32| {
        let t = i as f32 / n as f32;
        point(
            from.x + t * (to.x - from.x),
            from.y + t * (to.y - from.y),
            from.depth + t * (to.depth - from.depth),
            0.0,
        )
    };
    let cases = [
        // From far left onto the middle.
        (point(-5000.0, 32.0, 0.5, 0.0), point(40.0, 20.0, 0.5, 1.0)),
        // Across the whole target and out, the depth leaving 0..1 on the way.
        (
            point(-900.0, -300.0, -0.4, 0.0),
            point(900.0, 400.0, 1.3, 1.0),
        ),
        // On the target throughout.
        (point(3.0, 60.0, 0.2, 0.0), point(50.0, 1.0, 0.9, 1.0)),
    ];
    for (from, to) in cases {
        let n = segment_samples(from, to);
        let (first, last) = samples_on_target(from, to, n, &params).expect("on the target");
        assert!(last - first <= 64 + 2, "{first}..={last} of {n}");
        let every: Vec<u32> = (0..=n)
            .filter(|&i| inside(&along(from, to, i, n)))
            .collect();
        let kept: Vec<u32> = (first..=last)
            .filter(|&i| inside(&along(from, to, i, n)))
            .collect();
        assert_eq!(kept, every);
    }
    // Wholly off the target (right of it), or wholly beyond the far plane: none.
    let right = (point(70.0, 3.0, 0.5, 0.0), point(9000.0, 40.0, 0.5, 1.0));
    let beyond = (point(10.0, 10.0, 1.2, 0.0), point(30.0, 40.0, 1.5, 1.0));
    for (from, to) in [right, beyond] {
        let n = segment_samples(from, to);
        assert_eq!(samples_on_target(from, to, n, &params), None);
    }
}

/// A point nearer than the near plane is not on screen: a blade beside the camera,
/// just in front of it, would project far off the target and be stepped across all
/// of it. Planted fault: only points behind the camera refused: this one is then on
/// screen at x ≈ 1.8·10⁵ on a target 64 pixels wide.
#[test]
fn a_point_nearer_than_the_near_plane_is_not_on_screen() {
    let (params, _, view_proj, _) = looking_at_the_origin(64, 16.0, 2);
    // The camera stands at z = 10 looking down -z, its near plane at 0.1.
    let beside = Vec3::new(3.0, 1.0, 10.0 - 1e-3);
    assert_eq!(on_screen(beside, 0.0, view_proj, &params), None);
    let ahead = Vec3::new(0.0, 1.0, 10.0 - 0.2);
    assert!(on_screen(ahead, 0.0, view_proj, &params).is_some());
}
