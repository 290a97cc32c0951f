//! Collisions of blades with colliders (paper section 5.1, "Collision", where they
//! are spheres; here also capsules and boxes), and the collision strength η that
//! keeps trampled grass down for a while.

use crate::Blade;
use spirv_std::glam::{Quat, Vec3, Vec4, Vec4Swizzles};

/// Most colliders per frame: the collider buffer's room, and 64 words of one bit each
/// in a grid cell (`sim::grid`).
pub const MAX_COLLIDERS: usize = 2048;

/// A sphere: centre `a.xyz`, radius `a.w`.
pub const COLLIDER_SPHERE: u32 = 0;
/// A capsule (a character): the segment from `a.xyz` to `b.xyz`, radius `a.w`.
pub const COLLIDER_CAPSULE: u32 = 1;
/// A box (a vehicle, a crate): centre `a.xyz`, half extents `b.xyz`, turned by the
/// quaternion `rotation`, its edges rounded by `a.w` (0: sharp).
pub const COLLIDER_BOX: u32 = 2;
/// [`Collider::flags`]: the collider cuts the blades it holds (`sim::cut`) and does
/// not push them.
pub const COLLIDER_CUTS: u32 = 1;

/// One collider as the collider buffer holds it (`gpu::layout::BINDING_COLLIDERS`):
/// a sphere, a capsule or a box ([`COLLIDER_SPHERE`], [`COLLIDER_CAPSULE`],
/// [`COLLIDER_BOX`]).
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Collider {
    /// A sphere's or a box's centre, a capsule's first end (xyz); the radius, a box's
    /// rounding (w).
    pub a: Vec4,
    /// A capsule's second end, a box's half extents (xyz); w unused.
    pub b: Vec4,
    /// A box's rotation, a unit quaternion (x, y, z, w); the others' is unused.
    pub rotation: Vec4,
    /// A sphere around the whole collider (centre xyz, radius w): a point outside it
    /// is not pushed, found with one distance before the shape's own test.
    pub bound: Vec4,
    /// Which shape: `COLLIDER_*`.
    pub kind: u32,
    /// [`COLLIDER_CUTS`] where it cuts the blades it holds (`sim::cut`) instead of
    /// pushing them.
    pub flags: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}

impl Collider {
    /// A sphere of `radius` around `centre`.
    pub fn sphere(centre: Vec3, radius: f32) -> Self {
        Self::of(COLLIDER_SPHERE, centre.extend(radius), Vec4::ZERO, Vec4::W)
    }

    /// A sphere from centre (xyz) and radius (w), as the paper gives it.
    pub fn from_sphere(sphere: Vec4) -> Self {
        Self::sphere(sphere.xyz(), sphere.w)
    }

    /// A capsule of `radius` around the segment from `a` to `b`.
    pub fn capsule(a: Vec3, b: Vec3, radius: f32) -> Self {
        Self::of(COLLIDER_CAPSULE, a.extend(radius), b.extend(0.0), Vec4::W)
    }

    /// A box around `centre` with `half` extents, turned by `rotation`, its edges
    /// rounded by `rounding`.
    pub fn cuboid(centre: Vec3, half: Vec3, rotation: Quat, rounding: f32) -> Self {
        let r = Vec4::new(rotation.x, rotation.y, rotation.z, rotation.w);
        Self::of(COLLIDER_BOX, centre.extend(rounding), half.extend(0.0), r)
    }

    fn of(kind: u32, a: Vec4, b: Vec4, rotation: Vec4) -> Self {
        let mut c = Self {
            a,
            b,
            rotation,
            bound: Vec4::ZERO,
            kind,
            flags: 0,
            pad: [0; 2],
        };
        let (lo, hi) = c.bounds();
        let centre = (lo + hi) * 0.5;
        c.bound = centre.extend(match kind {
            COLLIDER_CAPSULE => 0.5 * (b.xyz() - a.xyz()).length() + a.w,
            COLLIDER_BOX => b.xyz().length() + a.w,
            _ => a.w,
        });
        c
    }

    /// The same volume as a cutter: it cuts the blades it holds (`sim::cut`) instead
    /// of pushing them.
    pub fn cutting(self) -> Self {
        Self {
            flags: self.flags | COLLIDER_CUTS,
            ..self
        }
    }

    /// Whether it cuts rather than pushes.
    pub fn cuts(&self) -> bool {
        self.flags & COLLIDER_CUTS != 0
    }

    /// Whether `p` may be inside: within the bounding sphere [`Collider::bound`].
    pub fn may_hold(&self, p: Vec3) -> bool {
        (p - self.bound.xyz()).length_squared() < self.bound.w * self.bound.w
    }

    /// The capsule the watch tests for this collider (`sim::grid`, [`within_capsule`]): its
    /// own for a capsule, one whose segment is its centre for a sphere, its bounding
    /// sphere for a box (the segment's first end and radius, its second end).
    pub fn watched(&self) -> (Vec4, Vec3) {
        if self.kind == COLLIDER_CAPSULE {
            (self.a, self.b.xyz())
        } else if self.kind == COLLIDER_BOX {
            (self.bound, self.bound.xyz())
        } else {
            (self.a, self.a.xyz())
        }
    }

    /// Whether `p` may be nearer the surface than `within`: nearer the capsule the
    /// watch tests ([`Collider::watched`], which holds the collider) than that.
    pub fn may_reach(&self, p: Vec3, within: f32) -> bool {
        within_capsule(self.watched(), p, within)
    }

    /// The displacement that moves `p` out of this collider onto its surface; zero
    /// outside it ([`penetration`] of the nearest point of a capsule's segment, or of
    /// a box's inner box: [`box_penetration`]).
    pub fn penetration(&self, p: Vec3) -> Vec3 {
        if self.kind == COLLIDER_CAPSULE {
            penetration(
                p,
                closest_on_segment(p, self.a.xyz(), self.b.xyz()).extend(self.a.w),
            )
        } else if self.kind == COLLIDER_BOX {
            box_penetration(p, self)
        } else {
            penetration(p, self.a)
        }
    }

    /// The distance from `p` to the collider's surface, negative inside: a point
    /// nearer `p` than this is outside, and [`Collider::penetration`] leaves it. The
    /// sphere's, the capsule's (from its segment's nearest point) and the rounded
    /// box's (from its inner box's nearest point, in the box's frame) signed
    /// distances (Quílez, *Distance functions*: `sdSphere`, `sdCapsule`,
    /// `sdRoundBox`); inside a box, at most its rounding's negative.
    pub fn gap(&self, p: Vec3) -> f32 {
        let nearest = if self.kind == COLLIDER_CAPSULE {
            closest_on_segment(p, self.a.xyz(), self.b.xyz())
        } else if self.kind == COLLIDER_BOX {
            let q = Quat::from_vec4(self.rotation);
            let local = q.conjugate() * (p - self.a.xyz());
            let half = self.b.xyz();
            q * local.clamp(-half, half) + self.a.xyz()
        } else {
            self.a.xyz()
        };
        (p - nearest).length() - self.a.w
    }

    /// The collider's axis-aligned bounds (least and greatest corner).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let r = Vec3::splat(self.a.w);
        let a = self.a.xyz();
        if self.kind == COLLIDER_CAPSULE {
            let b = self.b.xyz();
            (a.min(b) - r, a.max(b) + r)
        } else if self.kind == COLLIDER_BOX {
            let q = Quat::from_vec4(self.rotation);
            let h = self.b.xyz();
            // Each world axis reaches Σ |R_ij|·h_j.
            let reach =
                (q * Vec3::X * h.x).abs() + (q * Vec3::Y * h.y).abs() + (q * Vec3::Z * h.z).abs();
            (a - reach - r, a + reach + r)
        } else {
            (a - r, a + r)
        }
    }
}

/// Whether `p` is nearer than `within` to the capsule around the segment from
/// `a.xyz` to `b` of radius `a.w` (Quílez, *Distance functions*: `sdCapsule`).
/// Where this is false for every point `p` moved to on a path of length `within` or
/// less, no point of the path was inside it (the distance to the surface changes no
/// faster than the point moves), and a collider it holds moved none
/// ([`Collider::penetration`]).
pub fn within_capsule((a, b): (Vec4, Vec3), p: Vec3, within: f32) -> bool {
    (p - closest_on_segment(p, a.xyz(), b)).length() - a.w < within
}

/// The point of the segment from `a` to `b` nearest `p`.
pub fn closest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
    a + ab * t
}

/// Penetration of `p` into a (rounded) box: in the box's frame, outside its inner
/// box the rounding's sphere around the inner box's nearest point
/// ([`penetration`]); inside, out through the nearest face, plus the rounding.
pub fn box_penetration(p: Vec3, collider: &Collider) -> Vec3 {
    let q = Quat::from_vec4(collider.rotation);
    let half = collider.b.xyz();
    let local = q.conjugate() * (p - collider.a.xyz());
    let nearest = local.clamp(-half, half);
    let out = if local != nearest {
        penetration(local, nearest.extend(collider.a.w))
    } else {
        // Inside: the face with the least way out.
        let room = half - local.abs();
        let sign = Vec3::select(local.cmplt(Vec3::ZERO), -Vec3::ONE, Vec3::ONE);
        let way = room + Vec3::splat(collider.a.w);
        if room.x <= room.y && room.x <= room.z {
            Vec3::new(way.x * sign.x, 0.0, 0.0)
        } else if room.y <= room.z {
            Vec3::new(0.0, way.y * sign.y, 0.0)
        } else {
            Vec3::new(0.0, 0.0, way.z * sign.z)
        }
    };
    q * out
}

/// Penetration of point `p` into the sphere (centre xyz, radius w):
/// d(p) = min(|c − p| − ρ, 0)·normalize(c − p). Zero outside; inside, the
/// displacement that moves `p` out onto the surface.
pub fn penetration(p: Vec3, sphere: Vec4) -> Vec3 {
    let to_centre = sphere.truncate() - p;
    (to_centre.length() - sphere.w).min(0.0) * to_centre.normalize_or_zero()
}

/// Displacement of `v2` for one collider: d(v2) + 4·d(m), with m = ¼v0 + ½v1 + ¼v2 the
/// curve midpoint (moving v2 by δ moves m by about ¼δ, hence the 4).
pub fn displacement(blade: &Blade, collider: &Collider) -> Vec3 {
    collider.penetration(blade.tip()) + 4.0 * collider.penetration(blade.midpoint())
}

/// Pushes the tip out of `collider` (seeing the tip `blade` has) and returns the blade
/// with its new tip and `total` plus the displacement. `v1` is left for validation
/// to recompute.
pub fn push_out(blade: &Blade, collider: &Collider, total: Vec3) -> (Blade, Vec3) {
    let fixed = fixed_midpoint(blade);
    let d = tip_push(blade.tip(), fixed, collider);
    (blade.with_curve(blade.guide(), blade.tip() + d), total + d)
}

/// The part of the midpoint m = ¼v0 + ½v1 + ¼v2 a collision does not move,
/// ¼v0 + ½v1: the midpoint of the tip `v2` is this plus ¼v2.
pub fn fixed_midpoint(blade: &Blade) -> Vec3 {
    0.25 * blade.root() + 0.5 * blade.guide()
}

/// The displacement [`displacement`] of the tip `tip` of a blade whose midpoint is
/// `fixed` + ¼·`tip` ([`fixed_midpoint`]); zero, at the cost of two distances, where
/// neither point is within the collider's bounding sphere.
pub fn tip_push(tip: Vec3, fixed: Vec3, collider: &Collider) -> Vec3 {
    let mid = fixed + 0.25 * tip;
    if collider.may_hold(tip) || collider.may_hold(mid) {
        collider.penetration(tip) + 4.0 * collider.penetration(mid)
    } else {
        Vec3::ZERO
    }
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
        let d = displacement(&b, &Collider::from_sphere(sphere));
        // The midpoint (1.5 up) is outside: only d(v2) = (0.3 − 0.5)·(+X) = −0.2 X.
        assert!((d - Vec3::new(-0.2, 0.0, 0.0)).length() < 1e-6);
        let far = Vec4::new(5.0, 0.0, 5.0, 1.0);
        assert_eq!(displacement(&b, &Collider::from_sphere(far)), Vec3::ZERO);
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
    fn a_capsule_pushes_from_its_segment_and_a_box_through_its_nearest_face() {
        // A capsule lying along X at height 1, radius 0.5: a point 0.3 above its axis
        // goes to 0.5 above it, straight up; beyond an end, away from that end.
        let c = Collider::capsule(Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), 0.5);
        let p = Vec3::new(0.4, 1.3, 0.0);
        assert!((c.penetration(p) - Vec3::new(0.0, 0.2, 0.0)).length() < 1e-6);
        let beyond = Vec3::new(1.3, 1.0, 0.0);
        assert!((c.penetration(beyond) - Vec3::new(0.2, 0.0, 0.0)).length() < 1e-6);
        assert_eq!(c.penetration(Vec3::new(0.0, 2.0, 0.0)), Vec3::ZERO);
        assert_eq!(
            c.bounds(),
            (Vec3::new(-1.5, 0.5, -0.5), Vec3::new(1.5, 1.5, 0.5))
        );
        // A box 2 x 1 x 4 turned 90 degrees about Y (so 4 along X, 2 along Z): a point
        // 0.2 inside its +X face leaves through it; 0.1 inside +Z through that one.
        let turn = Quat::from_rotation_y(core::f32::consts::FRAC_PI_2);
        let b = Collider::cuboid(Vec3::ZERO, Vec3::new(1.0, 0.5, 2.0), turn, 0.0);
        let d = b.penetration(Vec3::new(1.8, 0.0, 0.3));
        assert!((d - Vec3::new(0.2, 0.0, 0.0)).length() < 1e-5, "{d}");
        let d = b.penetration(Vec3::new(0.3, 0.0, 0.9));
        assert!((d - Vec3::new(0.0, 0.0, 0.1)).length() < 1e-5, "{d}");
        assert_eq!(b.penetration(Vec3::new(0.0, 0.6, 0.0)), Vec3::ZERO);
        let (lo, hi) = b.bounds();
        assert!((lo - Vec3::new(-2.0, -0.5, -1.0)).length() < 1e-5, "{lo}");
        assert!((hi - Vec3::new(2.0, 0.5, 1.0)).length() < 1e-5, "{hi}");
        // Rounded by 0.25: a point 0.1 beyond the inner box's +Y face is pushed to
        // 0.25 beyond it.
        let r = Collider::cuboid(Vec3::ZERO, Vec3::ONE, Quat::IDENTITY, 0.25);
        let d = r.penetration(Vec3::new(0.5, 1.1, 0.0));
        assert!((d - Vec3::new(0.0, 0.15, 0.0)).length() < 1e-6, "{d}");
    }

    #[test]
    fn a_point_may_be_reached_within_its_distance_from_the_surface() {
        // A standing capsule of radius 0.3 from height 0.3 to 1.5: a point 0.2 beyond
        // its side is inside its bounding sphere (radius 0.9) but reached only
        // within more than 0.2.
        let c = Collider::capsule(Vec3::new(0.0, 0.3, 0.0), Vec3::new(0.0, 1.5, 0.0), 0.3);
        let p = Vec3::new(0.5, 1.0, 0.0);
        assert!(c.may_hold(p));
        assert!(c.may_reach(p, 0.25));
        assert!(!c.may_reach(p, 0.15));
        // Inside a sharp box the distance is 0: reached within any positive length,
        // and pushed.
        let b = Collider::cuboid(Vec3::ZERO, Vec3::ONE, Quat::IDENTITY, 0.0);
        let inside = Vec3::new(0.5, 0.2, 0.0);
        assert_ne!(b.penetration(inside), Vec3::ZERO);
        assert!(b.may_reach(inside, 1e-3));
        // A box's test is its bounding sphere's (radius √3): a point 0.1 beyond its
        // corner is reached within 0.11 and not within 0.09, and so is one 0.1 beyond
        // the sphere off its face.
        let corner = Vec3::ONE + Vec3::ONE.normalize() * 0.1;
        assert!(b.may_reach(corner, 0.11));
        assert!(!b.may_reach(corner, 0.09));
        let face = Vec3::X * (3f32.sqrt() + 0.1);
        assert!(b.may_reach(face, 0.11));
        // A sphere's own distance.
        let s = Collider::sphere(Vec3::Y, 0.5);
        assert!(s.may_reach(Vec3::new(0.0, 1.7, 0.0), 0.21));
        assert!(!s.may_reach(Vec3::new(0.0, 1.7, 0.0), 0.19));
    }

    #[test]
    fn two_spheres_push_in_turn() {
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0);
        // The first pushes the tip 0.2 along −X; the second (beyond it on −X) pushes
        // it back, seeing the moved tip 0.5 from its centre, 0.1 inside.
        let first = Collider::from_sphere(Vec4::new(0.3, 2.0, 0.0, 0.5));
        let second = Collider::from_sphere(Vec4::new(-0.7, 2.0, 0.0, 0.6));
        let (moved, total) = push_out(&b, &first, Vec3::ZERO);
        assert!((moved.tip() - Vec3::new(-0.2, 2.0, 0.0)).length() < 1e-6);
        assert!((total - Vec3::new(-0.2, 0.0, 0.0)).length() < 1e-6);
        let (moved, total) = push_out(&moved, &second, total);
        assert!(
            (moved.tip() - Vec3::new(-0.1, 2.0, 0.0)).length() < 1e-5,
            "{moved:?}"
        );
        assert!((total - Vec3::new(-0.1, 0.0, 0.0)).length() < 1e-5);
    }
}
