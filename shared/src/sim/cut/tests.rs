//! Unit tests of `cut`.

use super::*;
use crate::sim::validate::bezier_length;
use spirv_std::glam::Quat;

/// Hand-worked regrowth: a blade of 1.0 cut to 0.2, growing back over 10 s.
#[test]
fn regrowth_hand_worked() {
    assert_eq!(regrown(1.0, 0.2, 0.0, 10.0), 0.2);
    assert!((regrown(1.0, 0.2, 2.5, 10.0) - 0.4).abs() < 1e-6);
    assert!((regrown(1.0, 0.2, 5.0, 10.0) - 0.6).abs() < 1e-6);
    assert_eq!(regrown(1.0, 0.2, 10.0, 10.0), 1.0);
    assert_eq!(regrown(1.0, 0.2, 60.0, 10.0), 1.0);
    // A stub taller than the blade leaves it whole; no regrowth time: whole at once.
    assert_eq!(regrown(0.5, 0.8, 1.0, 10.0), 0.5);
    assert_eq!(regrown(1.0, 0.2, 0.0, 0.0), 1.0);
}

#[test]
fn cells_have_their_own_keys() {
    let a = cell_key(Vec3::new(0.1, 3.0, 0.1));
    assert_eq!(a, cell_key(Vec3::new(0.24, -1.0, 0.01)));
    assert_ne!(a, cell_key(Vec3::new(0.26, 0.0, 0.1)));
    assert_ne!(a, cell_key(Vec3::new(0.1, 0.0, -0.1)));
    // Negative cells, and none is the empty key.
    let b = cell_key(Vec3::new(-0.1, 0.0, -0.1));
    assert_ne!(b, a);
    assert_ne!(b, NO_CELL);
}

/// A cut blade keeps its root, direction and shape, shorter: its curve's length is
/// the cut height's share of its own.
#[test]
fn a_cut_blade_is_its_curve_scaled_to_the_stub() {
    let blade = Blade::at_rest(Vec3::new(1.0, 0.5, 2.0), Vec3::Y, 0.3, 1.2, 0.05, 4.0)
        .with_curve(Vec3::new(1.1, 1.5, 2.0), Vec3::new(1.5, 1.4, 2.1));
    let cut = cut_to(&blade, 0.3);
    assert_eq!(cut.root(), blade.root());
    assert_eq!(cut.height(), 0.3);
    assert_eq!(
        (cut.width(), cut.orientation()),
        (blade.width(), blade.orientation())
    );
    let length = |b: &Blade| bezier_length(b.root(), b.guide(), b.tip(), 64);
    assert!((length(&cut) / length(&blade) - 0.25).abs() < 1e-5);
    // No taller than it was.
    assert_eq!(cut_to(&blade, 2.0), blade);
}

/// A box mower 0.3 above the ground cuts the blade standing in it to 0.3; a blade
/// beside it, or already shorter than its lowest point, is not cut. A cutter below
/// the ground leaves the shortest stub.
#[test]
fn a_cutter_leaves_the_stub_below_its_lowest_point() {
    let mower = Collider::cuboid(
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(1.0, 0.2, 1.0),
        Quat::IDENTITY,
        0.0,
    )
    .cutting();
    assert!(mower.cuts());
    let standing = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 1.0, 0.05, 4.0);
    let stub = stub_left(&standing, &mower).expect("cut");
    assert!((stub - 0.3).abs() < 1e-6, "{stub}");
    let beside = Blade::at_rest(Vec3::new(3.0, 0.0, 0.0), Vec3::Y, 0.0, 1.0, 0.05, 4.0);
    assert_eq!(stub_left(&beside, &mower), None);
    let short = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 0.25, 0.05, 4.0);
    assert_eq!(stub_left(&short, &mower), None);
    let scythe =
        Collider::capsule(Vec3::new(-1.0, -0.1, 0.0), Vec3::new(1.0, -0.1, 0.0), 0.6).cutting();
    assert_eq!(stub_left(&standing, &scythe), Some(MIN_STUB));
}

/// The table: a cut is found by its cell, another cell's is not; a cell grown back
/// frees its slot for another; a cut is dropped only when every probe holds a cell
/// still growing back. Planted fault: `place` ignoring the regrowth (a grown cell's
/// slot never freed) fails the reuse.
#[test]
fn the_table_keeps_cuts_until_they_have_grown_back() {
    let regrow = 10.0;
    let mut table = CutTable::default();
    let key = cell_key(Vec3::new(5.0, 0.0, 7.0));
    assert!(table.cut(key, 0.1, 2.0, regrow));
    assert_eq!(
        find(&table.words, key),
        Some(Cut {
            time: 2.0,
            stub: 0.1
        })
    );
    assert_eq!(find(&table.words, cell_key(Vec3::new(5.3, 0.0, 7.0))), None);
    // Cut again: the new cut replaces the old.
    assert!(table.cut(key, 0.05, 4.0, regrow));
    assert_eq!(
        find(&table.words, key),
        Some(Cut {
            time: 4.0,
            stub: 0.05
        })
    );
    // Fill every probe of a home slot with other cells that hash there.
    let home = home_slot(key);
    let cell = |i: u32| Vec3::new((i % 8000) as f32, 0.0, (i / 8000) as f32) * CUT_CELL;
    let mut others = (0..8_000_000u32)
        .map(|i| cell_key(cell(i) + Vec3::splat(0.5 * CUT_CELL)))
        .filter(|&k| k != key && home_slot(k) == home);
    let mut crowd = Vec::new();
    while crowd.len() < CUT_PROBES as usize - 1 {
        let k = others.next().expect("enough cells hashing to one slot");
        assert!(table.cut(k, 0.1, 5.0, regrow));
        crowd.push(k);
    }
    let late = others.next().expect("one more");
    assert!(
        !table.cut(late, 0.1, 6.0, regrow),
        "every probe still growing back"
    );
    // Once they have grown back (the first cell at 14 s, the crowd at 15 s), it fits.
    assert!(table.cut(late, 0.1, 15.0, regrow));
    assert_eq!(find(&table.words, late).map(|c| c.time), Some(15.0));
}

/// A blade as the table leaves it: the regrowth formula for its cell's cut.
#[test]
fn a_blade_reads_its_cells_cut() {
    let mut table = CutTable::default();
    let blade = Blade::at_rest(Vec3::new(0.6, 0.0, 0.6), Vec3::Y, 0.0, 1.0, 0.05, 4.0);
    assert_eq!(as_cut(&blade, &table.words, 3.0, 10.0), blade);
    table.cut(cell_key(blade.root()), 0.2, 1.0, 10.0);
    // The frame that made the cut leaves it to the next.
    assert_eq!(as_cut(&blade, &table.words, 1.0, 10.0), blade);
    for now in [1.5, 3.5, 8.0, 11.0, 30.0] {
        let cut = as_cut(&blade, &table.words, now, 10.0);
        assert_eq!(cut.height(), regrown(1.0, 0.2, now - 1.0, 10.0));
    }
}

/// Through the colliders' grid, a blade meets the cutters a test of every collider
/// meets: among 300 walkers and 40 cutters, each blade's stub is the lowest any cutter
/// leaves, and walkers cut nothing. Planted fault: cutters not told from walkers
/// (every collider cutting) fails it.
#[test]
fn the_grid_finds_every_cutter_near_a_blade() {
    use crate::sim::colliders::{ColliderSet, fitted};
    use crate::sim::grid::GRID_SLOTS;
    let mut colliders = Vec::new();
    for i in 0..340u32 {
        let r = |k: u32| crate::noise::hash_unit(crate::noise::hash_u32(i * 4 + k));
        let at = Vec3::new(r(0) * 30.0, 0.0, r(1) * 30.0);
        colliders.push(if i % 17 == 0 {
            let half = Vec3::new(0.6, 0.2, 0.4);
            Collider::cuboid(
                at + Vec3::Y * (0.1 + 0.3 * r(2) + half.y),
                half,
                Quat::from_rotation_y(r(3) * 6.0),
                0.0,
            )
            .cutting()
        } else {
            Collider::capsule(at + Vec3::Y * 0.3, at + Vec3::Y * 1.5, 0.3)
        });
    }
    let count = colliders.len() as u32;
    let set = ColliderSet::new(&colliders, fitted(&colliders, 1.1, GRID_SLOTS));
    let near = set.nearby();
    let mut cut = 0;
    for k in 0..20_000u32 {
        let r = |j: u32| crate::noise::hash_unit(crate::noise::hash_u32(0x9e37 + k * 3 + j));
        let blade = Blade::at_rest(
            Vec3::new(r(0) * 30.0, 0.0, r(1) * 30.0),
            Vec3::Y,
            0.0,
            0.5 + 0.5 * r(2),
            0.05,
            4.0,
        );
        let every = colliders
            .iter()
            .filter(|c| c.cuts())
            .filter_map(|c| stub_left(&blade, c))
            .fold(blade.height(), f32::min);
        assert_eq!(cut_near(&blade, &near, count), every, "blade {k}");
        cut += usize::from(every < blade.height());
    }
    assert!(cut > 200, "{cut} blades cut");
}

/// A mower's blade thinner than the spacing of the points along a blade's curve
/// (0.05 high, at 0.3) still cuts a tall blade standing through it, upright or bent,
/// and misses one beside it. Planted fault: without the point at the cutter's level,
/// the upright blade of 2.5 is not cut.
#[test]
fn a_thin_cutter_cuts_a_tall_blade_through_it() {
    let blade_through = |tip: Vec3| {
        Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.5, 0.05, 4.0)
            .with_curve(Vec3::new(0.0, 2.5, 0.0).lerp(tip, 0.3), tip)
    };
    let thin = Collider::cuboid(
        Vec3::new(0.0, 0.325, 0.0),
        Vec3::new(1.0, 0.025, 1.0),
        Quat::IDENTITY,
        0.0,
    )
    .cutting();
    for tip in [Vec3::new(0.0, 2.5, 0.0), Vec3::new(1.2, 2.0, 0.3)] {
        let blade = crate::sim::validate::validate(&blade_through(tip));
        let stub = stub_left(&blade, &thin).expect("cut");
        assert!((stub - 0.3).abs() < 1e-5, "{stub}");
    }
    let beside = Blade::at_rest(Vec3::new(2.0, 0.0, 0.0), Vec3::Y, 0.0, 2.5, 0.05, 4.0);
    assert_eq!(stub_left(&beside, &thin), None);
}

/// A frame's cuts wait in their slots until the frame commits them: until then the
/// table reads as the frame found it (a cell cut before keeps its old cut, a cell
/// never cut reads as uncut), two cuts of one cell in a frame leave the lower stub
/// whichever comes first, and the commit gives the cut the frame's time. Planted
/// fault: a cut written straight into its slot's time and stub failed the first read
/// (the cell cut before read as never cut: its blades stood at full height for the
/// frame).
#[test]
fn a_frames_cuts_wait_for_its_commit() {
    let regrow = 10.0;
    let mut table = CutTable::default();
    let blade = Blade::at_rest(Vec3::new(0.6, 0.0, 0.6), Vec3::Y, 0.0, 1.0, 0.05, 4.0);
    let fresh = Blade::at_rest(Vec3::new(3.1, 0.0, 0.6), Vec3::Y, 0.0, 1.0, 0.05, 4.0);
    let key = cell_key(blade.root());
    assert!(table.cut(key, 0.3, 1.0, regrow));
    let before = as_cut(&blade, &table.words, 5.0, regrow);
    assert_eq!(before.height(), regrown(1.0, 0.3, 4.0, regrow));
    // The frame at 5 s cuts the cell twice, the higher stub second, and a new cell.
    assert!(table.pend(key, 0.1, 5.0, regrow));
    assert!(table.pend(key, 0.2, 5.0, regrow));
    assert!(table.pend(cell_key(fresh.root()), 0.1, 5.0, regrow));
    assert_eq!(as_cut(&blade, &table.words, 5.0, regrow), before);
    assert_eq!(as_cut(&fresh, &table.words, 5.0, regrow), fresh);
    table.commit(5.0);
    assert_eq!(
        find(&table.words, key),
        Some(Cut {
            time: 5.0,
            stub: 0.1
        })
    );
    // The next frame reads both cuts.
    let after = regrown(1.0, 0.1, 1.0, regrow);
    assert_eq!(as_cut(&blade, &table.words, 6.0, regrow).height(), after);
    assert_eq!(as_cut(&fresh, &table.words, 6.0, regrow).height(), after);
}

/// A cell cut again while a slot before its own has grown back keeps its own slot:
/// it does not take the freed one, which `find` would reach first (reading the freed
/// slot's old cut, grown back, while the frame's cut waits for its commit). Planted
/// fault: `place` taking the first free probe failed it.
#[test]
fn a_cell_cut_again_keeps_its_slot() {
    let regrow = 10.0;
    let mut table = CutTable::default();
    let key = cell_key(Vec3::new(5.0, 0.0, 7.0));
    let home = home_slot(key);
    let cell = |i: u32| Vec3::new((i % 8000) as f32, 0.0, (i / 8000) as f32) * CUT_CELL;
    let other = (0..8_000_000u32)
        .map(|i| cell_key(cell(i) + Vec3::splat(0.5 * CUT_CELL)))
        .find(|&k| k != key && home_slot(k) == home)
        .expect("a cell hashing to the same slot");
    // The other cell takes the home slot at 1 s, ours the next at 2 s.
    assert!(table.cut(other, 0.1, 1.0, regrow));
    assert!(table.cut(key, 0.1, 2.0, regrow));
    // At 11.5 s the other has grown back; ours is cut again and waits for the commit.
    assert!(table.pend(key, 0.05, 11.5, regrow));
    assert_eq!(find(&table.words, key).map(|c| c.time), Some(2.0));
    table.commit(11.5);
    assert_eq!(
        find(&table.words, key),
        Some(Cut {
            time: 11.5,
            stub: 0.05
        })
    );
}
