//! One blade of grass: a quadratic Bezier curve plus four scalars (paper section 3).

use spirv_std::glam::{Vec3, Vec4};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// A blade as the GPU stores it: four `vec4`, 64 bytes, the curve's two moving
/// points first: the simulation moves only `v1` and `v2`, so the compute pass writes
/// back one 32-byte memory sector a blade rather than all 64 bytes.
///
/// | field | xyz | w |
/// |---|---|---|
/// | `v1` | Bezier guide above `v0` | height h |
/// | `v2` | tip guide, where forces act | width w |
/// | `v0` | root on the surface | orientation θ (radians) |
/// | `up` | unit surface normal at `v0` | stiffness s |
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Blade {
    /// Middle control point (xyz) and height h (w).
    pub v1: Vec4,
    /// Tip control point (xyz) and width w (w).
    pub v2: Vec4,
    /// Root position (xyz) and orientation θ (w).
    pub v0: Vec4,
    /// Surface normal (xyz) and stiffness s (w).
    pub up: Vec4,
}

impl Blade {
    /// A blade standing at rest: `v1 = v2 = v0 + h·up`.
    pub fn at_rest(
        root: Vec3,
        up: Vec3,
        orientation: f32,
        height: f32,
        width: f32,
        stiffness: f32,
    ) -> Self {
        let tip = root + up * height;
        Self {
            v0: root.extend(orientation),
            v1: tip.extend(height),
            v2: tip.extend(width),
            up: up.extend(stiffness),
        }
    }

    /// Root position `v0`.
    pub fn root(&self) -> Vec3 {
        self.v0.truncate()
    }
    /// Middle control point `v1`.
    pub fn guide(&self) -> Vec3 {
        self.v1.truncate()
    }
    /// Tip control point `v2`.
    pub fn tip(&self) -> Vec3 {
        self.v2.truncate()
    }
    /// Unit surface normal `up`.
    pub fn up_dir(&self) -> Vec3 {
        self.up.truncate()
    }
    /// Orientation θ in radians.
    pub fn orientation(&self) -> f32 {
        self.v0.w
    }
    /// Height h.
    pub fn height(&self) -> f32 {
        self.v1.w
    }
    /// Width w (full width; the blade spans ±w/2 around the curve).
    pub fn width(&self) -> f32 {
        self.v2.w
    }
    /// Stiffness s of the recovery force.
    pub fn stiffness(&self) -> f32 {
        self.up.w
    }

    /// The blade with new control points `v1`, `v2`; the scalars stay as they are.
    pub fn with_curve(&self, v1: Vec3, v2: Vec3) -> Self {
        Self {
            v0: self.v0,
            v1: v1.extend(self.v1.w),
            v2: v2.extend(self.v2.w),
            up: self.up,
        }
    }

    /// The blade drawn `width` wide; the rest as it is.
    pub fn with_width(&self, width: f32) -> Self {
        Self {
            v2: self.v2.truncate().extend(width),
            ..*self
        }
    }

    /// Width direction t1: unit vector at angle θ in the plane perpendicular to `up`.
    pub fn width_dir(&self) -> Vec3 {
        width_dir(self.up_dir(), self.orientation())
    }

    /// Front direction f = normalize(up × t1), the side the blade faces.
    pub fn front_dir(&self) -> Vec3 {
        self.up_dir().cross(self.width_dir()).normalize()
    }

    /// Curve midpoint m = ¼v0 + ½v1 + ¼v2 (the Bezier curve at parameter ½).
    pub fn midpoint(&self) -> Vec3 {
        0.25 * self.root() + 0.5 * self.guide() + 0.25 * self.tip()
    }
}

/// Two unit tangents (e1, e2) spanning the plane perpendicular to `up`, with
/// e1 = +X and e2 = +Z for `up` = +Y, so θ means the same on a flat ground everywhere.
pub fn tangent_frame(up: Vec3) -> (Vec3, Vec3) {
    // Project +X (or +Z when up is close to X) onto the tangent plane.
    let reference = if up.x.abs() < 0.9 { Vec3::X } else { Vec3::Z };
    let e1 = (reference - up * up.dot(reference)).normalize();
    let e2 = e1.cross(up);
    (e1, e2)
}

/// Width direction t1 at angle θ around `up`: (cos θ, 0, sin θ) for `up` = +Y.
pub fn width_dir(up: Vec3, orientation: f32) -> Vec3 {
    let (e1, e2) = tangent_frame(up);
    e1 * orientation.cos() + e2 * orientation.sin()
}

/// Heights of generated blades are drawn in this range (the course's defaults).
pub const HEIGHT: (f32, f32) = (1.3, 2.5);
/// Widths are drawn in this range (before widening).
pub const WIDTH: (f32, f32) = (0.1, 0.14);
/// Stiffnesses are drawn in this range.
pub const STIFFNESS: (f32, f32) = (7.0, 13.0);

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn layout_is_four_vec4() {
        assert_eq!(core::mem::size_of::<Blade>(), 64);
    }

    #[test]
    fn width_dir_on_flat_ground_matches_paper() {
        let t = 0.7_f32;
        assert!(close(
            width_dir(Vec3::Y, t),
            Vec3::new(t.cos(), 0.0, t.sin())
        ));
    }

    #[test]
    fn frame_is_orthonormal_for_any_up() {
        for up in [
            Vec3::Y,
            Vec3::X,
            -Vec3::Z,
            Vec3::new(1.0, 2.0, 3.0).normalize(),
        ] {
            let (e1, e2) = tangent_frame(up);
            assert!(e1.dot(up).abs() < 1e-6 && e2.dot(up).abs() < 1e-6);
            assert!(e1.dot(e2).abs() < 1e-6);
            assert!((e1.length() - 1.0).abs() < 1e-6 && (e2.length() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn at_rest_stands_straight_and_midpoint_is_on_the_curve() {
        let b = Blade::at_rest(Vec3::new(1.0, 0.0, 2.0), Vec3::Y, 0.3, 2.0, 0.1, 9.0);
        assert!(close(b.tip(), Vec3::new(1.0, 2.0, 2.0)));
        assert!(close(b.guide(), b.tip()));
        // m = ¼·(1,0,2) + ½·(1,2,2) + ¼·(1,2,2) = (1, 1.5, 2)
        assert!(close(b.midpoint(), Vec3::new(1.0, 1.5, 2.0)));
        assert!(b.front_dir().dot(b.width_dir()).abs() < 1e-6);
    }
}
