//! Collisions of blades with spheres (paper section 5.1, "Collision"), and the
//! collision strength η that keeps trampled grass down for a while.

use crate::Blade;
use spirv_std::glam::{Vec3, Vec4};

/// Most sphere colliders per frame.
pub const MAX_COLLIDERS: usize = 16;

/// Penetration of point `p` into the sphere (centre xyz, radius w):
/// d(p) = min(|c − p| − ρ, 0)·normalize(c − p). Zero outside; inside, the
/// displacement that moves `p` out onto the surface.
pub fn penetration(p: Vec3, sphere: Vec4) -> Vec3 {
    let to_centre = sphere.truncate() - p;
    (to_centre.length() - sphere.w).min(0.0) * to_centre.normalize_or_zero()
}

/// Displacement of `v2` for one sphere: d(v2) + 4·d(m), with m = ¼v0 + ½v1 + ¼v2 the
/// curve midpoint (moving v2 by δ moves m by about ¼δ, hence the 4).
pub fn sphere_displacement(blade: &Blade, sphere: Vec4) -> Vec3 {
    penetration(blade.tip(), sphere) + 4.0 * penetration(blade.midpoint(), sphere)
}

/// Pushes the tip out of the first `count` spheres in turn (each sees the tip the
/// previous one left) and returns the blade with its new tip and the total
/// displacement. `v1` is left for validation to recompute.
pub fn collide(blade: &Blade, spheres: &[Vec4; MAX_COLLIDERS], count: u32) -> (Blade, Vec3) {
    let mut b = *blade;
    let mut total = Vec3::ZERO;
    let mut i = 0;
    while i < (count as usize).min(MAX_COLLIDERS) {
        let d = sphere_displacement(&b, spheres[i]);
        b = b.with_curve(b.guide(), b.tip() + d);
        total += d;
        i += 1;
    }
    (b, total)
}

/// Most collision strength a blade keeps: recovery is already at its floor
/// (max(1 − η, 0.1)) from η = 0.9, and a cap keeps a long contact from holding the
/// grass down for ever.
pub const MAX_STRENGTH: f32 = 1.0;

/// Collision strength η after a step of `dt`: it decays linearly at `decay` per
/// second, never below 0, and grows by the length of the displacement just applied,
/// up to [`MAX_STRENGTH`].
pub fn update_strength(strength: f32, displacement: Vec3, decay: f32, dt: f32) -> f32 {
    ((strength - decay * dt).max(0.0) + displacement.length()).min(MAX_STRENGTH)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_inside_ends_on_the_surface_and_outside_nothing_moves() {
        let sphere = Vec4::new(0.0, 1.0, 0.0, 0.5);
        let inside = Vec3::new(0.2, 1.1, 0.0);
        let moved = inside + penetration(inside, sphere);
        assert!(((moved - sphere.truncate()).length() - 0.5).abs() < 1e-6);
        // Pushed away from the centre, along the same ray.
        let before = (inside - sphere.truncate()).normalize();
        let after = (moved - sphere.truncate()).normalize();
        assert!((before - after).length() < 1e-6);
        assert_eq!(penetration(Vec3::new(2.0, 1.0, 0.0), sphere), Vec3::ZERO);
        // At the centre there is no direction: no displacement rather than NaN.
        assert_eq!(penetration(sphere.truncate(), sphere), Vec3::ZERO);
    }

    #[test]
    fn a_sphere_on_the_tip_pushes_it_out() {
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0);
        // Sphere of radius 0.5 centred 0.3 beside the tip (2 units up).
        let sphere = Vec4::new(0.3, 2.0, 0.0, 0.5);
        let d = sphere_displacement(&b, sphere);
        // The midpoint (1.5 up) is outside: only d(v2) = (0.3 − 0.5)·(+X) = −0.2 X.
        assert!((d - Vec3::new(-0.2, 0.0, 0.0)).length() < 1e-6);
        let far = Vec4::new(5.0, 0.0, 5.0, 1.0);
        assert_eq!(sphere_displacement(&b, far), Vec3::ZERO);
    }

    #[test]
    fn strength_grows_on_contact_and_decays_to_zero() {
        // A long contact saturates at MAX_STRENGTH.
        assert_eq!(update_strength(0.9, Vec3::X, 0.5, 0.1), MAX_STRENGTH);
        let mut s = update_strength(0.0, Vec3::new(0.3, 0.0, 0.4), 0.5, 0.1);
        assert!((s - 0.5).abs() < 1e-6);
        for _ in 0..9 {
            s = update_strength(s, Vec3::ZERO, 0.5, 0.1);
        }
        assert!((s - 0.05).abs() < 1e-5, "linear decay: {s}");
        s = update_strength(s, Vec3::ZERO, 0.5, 0.1);
        assert_eq!(s, 0.0);
        assert_eq!(update_strength(s, Vec3::ZERO, 0.5, 0.1), 0.0);
    }

    #[test]
    fn two_spheres_push_in_turn_and_unused_slots_are_ignored() {
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0);
        let mut spheres = [Vec4::new(100.0, 0.0, 0.0, 0.1); MAX_COLLIDERS];
        // First pushes the tip 0.2 along −X, the second (beyond it on −X) pushes back.
        spheres[0] = Vec4::new(0.3, 2.0, 0.0, 0.5);
        spheres[1] = Vec4::new(-0.7, 2.0, 0.0, 0.6);
        let (moved, total) = collide(&b, &spheres, 1);
        assert!((moved.tip() - Vec3::new(-0.2, 2.0, 0.0)).length() < 1e-6);
        assert!((total - Vec3::new(-0.2, 0.0, 0.0)).length() < 1e-6);
        // The second sphere sees the moved tip: 0.5 from its centre, 0.1 inside.
        let (moved, total) = collide(&b, &spheres, 2);
        assert!(
            (moved.tip() - Vec3::new(-0.1, 2.0, 0.0)).length() < 1e-5,
            "{moved:?}"
        );
        assert!((total - Vec3::new(-0.1, 0.0, 0.0)).length() < 1e-5);
        // A sphere in an unused slot (count 0) does nothing, even when it touches.
        spheres[0] = Vec4::new(0.0, 2.0, 0.0, 1.0);
        assert_eq!(collide(&b, &spheres, 0), (b, Vec3::ZERO));
    }
}
