//! Walkers: capsules the size of people wandering over a scene's ground, each a
//! collider of the frame (`shared::sim::collide::COLLIDER_CAPSULE`); and mowers, boxes
//! driving over it that cut the grass (`shared::sim::cut`). Where each is at a
//! simulated time is a function of that time alone, so a headless run, a bench and the
//! viewer put the same walkers in the same places whatever their frame rate.

use crate::scene::{Scene, SceneKind};
use glam::{Vec2, Vec3};
use shared::noise::{hash_u32, hash_unit};
use shared::sim::collide::{Collider, MAX_COLLIDERS};
use shared::world::terrain::{path_centre, valley_height};

/// Most walkers: half the collider buffer's room (the rest for the ball and a host
/// program's own colliders).
pub const MAX_WALKERS: u32 = MAX_COLLIDERS as u32 / 2;

/// A walker's radius (shoulders) and height, scene units (metres in the valley).
pub const WALKER_SIZE: (f32, f32) = (0.3, 1.8);

/// Most mowers.
pub const MAX_MOWERS: u32 = 64;

/// A mower's half extents along its way, up and across, scene units: 0.8 long, 1.2
/// wide, its deck 0.16 tall.
pub const MOWER_HALF: Vec3 = Vec3::new(0.4, 0.08, 0.6);

/// Height of a mower's deck above the ground: the stub it leaves.
pub const MOWER_CUT: f32 = 0.1;

/// Walking speeds, units a second: a stroll to a brisk walk.
const SPEED: (f32, f32) = (0.8, 1.8);

/// The ground the walkers wander: a square (centre, half its side) and how they stand
/// on it.
#[derive(Clone, Debug)]
pub struct Walkers {
    count: u32,
    mowers: u32,
    centre: Vec2,
    half: f32,
    seed: u32,
}

impl Walkers {
    /// `count` walkers (at most [`MAX_WALKERS`]) over `scene`: in the valley, a square
    /// of 96 units around the first 60 units of its path (where the flight camera
    /// flies); elsewhere the scene's ground seen from above.
    pub fn new(scene: &Scene, count: u32) -> Self {
        let (centre, half) = if scene.kind == SceneKind::Valley {
            let z = -30.0;
            (Vec2::new(path_centre(z).0, z), 48.0)
        } else {
            scene.paint_square()
        };
        Self {
            count: count.min(MAX_WALKERS),
            mowers: 0,
            centre,
            half,
            seed: scene.seed as u32,
        }
    }

    /// This set with `mowers` mowers (at most [`MAX_MOWERS`]) driving the same
    /// ground.
    pub fn with_mowers(&self, mowers: u32) -> Self {
        Self {
            mowers: mowers.min(MAX_MOWERS),
            ..self.clone()
        }
    }

    /// How many mowers there are.
    pub fn mowers(&self) -> u32 {
        self.mowers
    }

    /// How many there are.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// This set with `count` walkers (the first ones keep their ways).
    pub fn with_count(&self, count: u32) -> Self {
        Self {
            count: count.min(MAX_WALKERS),
            ..self.clone()
        }
    }

    /// Walker `i`'s place on the ground (x, z) at `time`: a straight walk at its own
    /// speed and heading, turned back at the square's edges (a triangle wave on each
    /// axis), with a sway of a metre across it.
    pub fn place(&self, i: u32, time: f32) -> Vec2 {
        let r = |k: u32| hash_unit(self.seed ^ hash_u32(i * 8 + k));
        let heading = r(0) * std::f32::consts::TAU;
        let speed = SPEED.0 + (SPEED.1 - SPEED.0) * r(1);
        let dir = Vec2::new(heading.cos(), heading.sin());
        let sway = (0.9 * time + r(2) * 6.0).sin() * Vec2::new(-dir.y, dir.x);
        let side = 2.0 * self.half;
        let start = Vec2::new(r(3), r(4)) * side;
        let travelled = start + dir * speed * time + sway;
        let bounce = |u: f32| {
            let t = (u / side).rem_euclid(2.0);
            side * (1.0 - (t - 1.0).abs())
        };
        self.centre - Vec2::splat(self.half) + Vec2::new(bounce(travelled.x), bounce(travelled.y))
    }

    /// The walkers' capsules at `time`, standing on `scene`'s ground (the valley's
    /// terrain, rocks aside; else straight down onto its surface, upright along its
    /// normal on a planet); then the mowers' boxes, each swept over the frame of
    /// `seconds` before `time`: a box along its way from where it was to where it is
    /// (the union of its places on a straight drive), so a slow frame leaves no gap.
    pub fn colliders(&self, scene: &Scene, time: f32, seconds: f32) -> Vec<Collider> {
        let (radius, height) = WALKER_SIZE;
        let walkers = (0..self.count).filter_map(|i| {
            let (foot, up) = self.stand(scene, self.place(i, time))?;
            Some(Collider::capsule(
                foot + up * radius,
                foot + up * (height - radius),
                radius,
            ))
        });
        let mowers = (0..self.mowers).filter_map(|m| {
            // Mowers take their ways after every walker's.
            let i = MAX_WALKERS + m;
            let (to, from) = (self.place(i, time), self.place(i, time - seconds.max(1e-3)));
            let way = to - from;
            let along = if way.length() > 1e-6 {
                way.normalize()
            } else {
                (to - self.place(i, time - 0.1)).normalize_or(Vec2::X)
            };
            let (foot, up) = self.stand(scene, 0.5 * (to + from))?;
            let half = MOWER_HALF + Vec3::X * 0.5 * way.length();
            let turn = glam::Quat::from_rotation_arc(Vec3::X, Vec3::new(along.x, 0.0, along.y));
            let centre = foot + up * (MOWER_CUT + MOWER_HALF.y);
            Some(Collider::cuboid(centre, half, turn, 0.0).cutting())
        });
        walkers.chain(mowers).collect()
    }

    /// Where a collider at ground point `at` stands: the valley's terrain, else
    /// straight down onto the scene's surface (upright along its normal on a planet).
    fn stand(&self, scene: &Scene, at: Vec2) -> Option<(Vec3, Vec3)> {
        if scene.kind == SceneKind::Valley {
            return Some((Vec3::new(at.x, valley_height(at), at.y), Vec3::Y));
        }
        let p = crate::collider::drop_onto(&scene.solid, at)?;
        let up = if scene.gravity_centre.is_some() {
            p.normal
        } else {
            Vec3::Y
        };
        Some((p.position, up))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walkers_stay_in_their_square_and_walk_at_their_pace() {
        let scene = Scene::plane(2048, 3);
        let walkers = Walkers::new(&scene, 200);
        let (centre, half) = scene.paint_square();
        let dt = 0.1;
        for i in 0..200 {
            for step in 0..100 {
                let t = step as f32 * dt;
                let (a, b) = (walkers.place(i, t), walkers.place(i, t + dt));
                let off = (a - centre).abs().max_element();
                assert!(off <= half + 1e-3, "walker {i} at {a} off its square");
                // Walking speed plus the sway's, never a jump.
                assert!(
                    a.distance(b) <= (SPEED.1 + 1.0) * dt,
                    "walker {i}: {a} → {b}"
                );
            }
        }
        // Standing on the plane, a person's height.
        let capsules = walkers.colliders(&scene, 3.0, 1.0 / 60.0);
        assert_eq!(capsules.len(), 200);
        for c in &capsules {
            let (lo, hi) = c.bounds();
            assert!(
                lo.y.abs() < 1e-4 && (hi.y - WALKER_SIZE.1).abs() < 1e-4,
                "{lo} {hi}"
            );
        }
        // The same walkers at the same time, whatever came before.
        assert_eq!(walkers.colliders(&scene, 3.0, 1.0 / 60.0), capsules);
        assert_eq!(walkers.with_count(5000).count(), MAX_WALKERS);
    }

    /// A mower cuts, its deck at the cut height above the plane, and a slow frame's
    /// box covers the way from where it was to where it is.
    #[test]
    fn mowers_cut_along_their_way() {
        let scene = Scene::plane(2048, 3);
        let mowers = Walkers::new(&scene, 0).with_mowers(3);
        let boxes = mowers.colliders(&scene, 5.0, 1.0 / 60.0);
        assert_eq!(boxes.len(), 3);
        for b in &boxes {
            assert!(b.cuts());
            let (lo, hi) = b.bounds();
            assert!((lo.y - MOWER_CUT).abs() < 1e-4, "{lo}");
            assert!((hi.y - MOWER_CUT - 2.0 * MOWER_HALF.y).abs() < 1e-4, "{hi}");
        }
        // Half a second: the box holds where the mower was and where it is.
        let swept = mowers.colliders(&scene, 5.0, 0.5);
        for (m, b) in swept.iter().enumerate() {
            let i = MAX_WALKERS + m as u32;
            for t in [4.5, 4.75, 5.0] {
                let at = mowers.place(i, t);
                let p = Vec3::new(at.x, MOWER_CUT + MOWER_HALF.y, at.y);
                assert_ne!(b.penetration(p), Vec3::ZERO, "mower {m} at {t}: {at}");
            }
        }
        assert_eq!(mowers.with_mowers(1000).mowers(), MAX_MOWERS);
    }
}
