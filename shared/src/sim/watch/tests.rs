//! Unit tests of `watch`.

use super::*;
use crate::sim::colliders::{ColliderSet, fitted};
use crate::sim::grid::tests::{Rng, crowd};

/// Hand-worked places in the wrapped grid of 64 (4 x 4 columns, 4 layers): cube
/// (1, 2, 3) at 2·16 + 3·4 + 1 = 45, (−1, −1, −1) at the last, 63; a step of 4 along
/// any axis is the same place, and one along x the next; of 128 places (8 along x,
/// 4 along z) (5, 1, 2) is at 32 + 16 + 5 = 53; fewer than 4 places are all one.
#[test]
fn a_cube_has_its_place_in_the_wrapped_grid() {
    assert_eq!(wrapped(IVec3::new(1, 2, 3), 64), 45);
    assert_eq!(wrapped(IVec3::new(-1, -1, -1), 64), 63);
    for c in [
        IVec3::new(0, 0, 0),
        IVec3::new(-7, 3, 11),
        IVec3::new(100, -2, -50),
    ] {
        for step in [IVec3::X, IVec3::Y, IVec3::Z] {
            assert_eq!(wrapped(c + 4 * step, 64), wrapped(c, 64), "{c}");
        }
        if c.x % 4 != 3 {
            assert_eq!(wrapped(c + IVec3::X, 64), wrapped(c, 64) + 1, "{c}");
        }
    }
    assert_eq!(wrapped(IVec3::new(5, 1, 2), 128), 53);
    assert_eq!(wrapped(IVec3::new(5, 1, 2), 1), 0);
}

/// Over a crowd of 1,500 colliders (a collider to 107 square units, as 1,024
/// walkers on the bench's 4 M-blade field), a watch cube whose mark is set has a
/// slot that counts a collider (`watch_collider` sets both), and the marks, four
/// times as long a period as the slots, share fewer cubes: of 20,000 points,
/// measured 7,536 in a marked cube against 8,352 in a counting slot. Planted faults:
/// the marks not set (none marked), and marks of the slots' period (8,352 and 8,352),
/// each failed.
#[test]
fn a_marked_cube_has_a_slot_that_counts_a_collider() {
    let colliders = crowd(1500, 400.0);
    let grid = fitted(&colliders, 2.75, 1 << 16);
    let set = ColliderSet::new(&colliders, grid);
    let words = set.words();
    assert_eq!(grid.words(), words.len());
    let mut rng = Rng(5);
    let (mut marked, mut counted) = (0, 0);
    for _ in 0..20_000 {
        let p = Vec3::new(
            (rng.next() - 0.5) * 400.0,
            3.0 * rng.next() - 0.5,
            (rng.next() - 0.5) * 400.0,
        );
        let cube = grid.watch_cube(p);
        let (word, bit) = grid.watch_mark(cube);
        let count = words[grid.watch_base(cube) + COUNT_WORD];
        assert!(words[word] & bit == 0 || count > 0, "{cube}");
        marked += usize::from(words[word] & bit != 0);
        counted += usize::from(count > 0);
    }
    println!("{marked} marked, {counted} counted");
    assert!(marked > 6000, "{marked} of 20,000 points marked");
    assert!(marked < counted, "{marked} marked, {counted} counted");
}

/// A blade's tip 0.2 units from a ball of radius 0.5: with a travel 1e-4 short of
/// the gap it may have touched (the margin covers the rounding of the travel and the
/// distances), with a travel 2e-3 short it may not (the margin is no wider). Planted
/// faults: a margin of −0.05 failed the first, one of 0.1 the second.
#[test]
fn a_grown_sphere_holds_a_point_within_its_travel_and_margin() {
    let ball = Vec4::new(2.7, 1.0, 0.0, 0.5);
    let colliders = [Collider::from_sphere(ball)];
    let set = ColliderSet::new(&colliders, fitted(&colliders, 2.75, 64));
    let near = set.nearby();
    let blade = Blade::at_rest(Vec3::new(2.0, 0.0, 0.0), Vec3::Y, 0.0, 1.0, 0.1, 5.0);
    let gap = blade.tip().distance(ball.truncate()) - ball.w;
    assert!((gap - 0.2).abs() < 1e-6);
    assert!(blade.midpoint().distance(ball.truncate()) - ball.w > gap);
    let short = |by: f32| Vec2::new(gap - by, 0.0);
    assert!(near.may_have_touched(&blade, short(1e-4)));
    assert!(!near.may_have_touched(&blade, short(2e-3)));
}

/// The watch against every collider: over a crowd of 1,500 capsules, spheres and
/// boxes (a collider to 107 square units, as 1,024 walkers on the bench's 4 M-blade
/// field), for tips and midpoints scattered over the crowd's square with travels up
/// to a tenth of a unit (one in ten up to 1.5), the watch's slot says a point may
/// have been touched wherever a test of every pushing collider's capsule
/// ([`Collider::watched`]) does, and otherwise only where its slot is full or the
/// points spread past the allowance. Measured: 918 of 20,000 touched by the test of
/// every collider, 1,170 more from full slots and the allowance (most of the points
/// that travelled far). Planted faults: the
/// watch's cubes grown by the margin alone, or the allowance not asked, each missed
/// a touch; every slot taken as full gave 11,268 more, and the crowd spread over
/// twice the side 253 touched, and each failed.
#[test]
fn the_watch_finds_every_collider_a_test_of_all_finds() {
    let colliders = crowd(1500, 400.0);
    let set = ColliderSet::new(&colliders, fitted(&colliders, 2.75, 1 << 16));
    let near = set.nearby();
    let mut rng = Rng(11);
    let (mut touched, mut more) = (0, 0);
    for i in 0..20_000 {
        let root = Vec3::new((rng.next() - 0.5) * 400.0, 0.0, (rng.next() - 0.5) * 400.0);
        let lean = Vec3::new(rng.next() - 0.5, 0.0, rng.next() - 0.5);
        let height = 0.5 + 2.0 * rng.next();
        let blade = Blade::at_rest(root, Vec3::Y, 0.0, height, 0.1, 5.0).with_curve(
            root + Vec3::Y * height,
            root + (Vec3::Y + lean) * height * 0.9,
        );
        let far = if i % 10 == 0 { 1.5 } else { 0.1 };
        let travel = Vec2::new(far * rng.next(), far * rng.next());
        let (tip, mid) = (blade.tip(), blade.midpoint());
        let all = colliders.iter().any(|c| {
            !c.cuts()
                && (c.may_reach(tip, travel.x + WATCH_MARGIN)
                    || c.may_reach(mid, travel.y + WATCH_MARGIN))
        });
        let watched = near.may_have_touched(&blade, travel);
        assert!(watched || !all, "{blade:?} {travel}: missed");
        touched += usize::from(all);
        more += usize::from(watched && !all);
    }
    assert!(touched > 450, "{touched} touched");
    assert!(more < 2000, "{more} more watched");
}
