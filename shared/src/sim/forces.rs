//! The three forces acting on the tip `v2` (paper section 5.1).

use crate::Blade;
use spirv_std::glam::{Vec3, Vec4};

/// Environment gravity gE = normalize(D.xyz)·D.w, with D the gravity direction and
/// acceleration (paper eq. 2 without the gravity centre term).
pub fn environment_gravity(d: Vec4) -> Vec3 {
    d.truncate().normalize_or_zero() * d.w
}

/// Environment gravity blended towards a gravity centre (paper eq. 2):
/// gE = (1 − t)·normalize(D.xyz)·D.w + t·normalize(C.xyz − v2)·C.w, with C the centre
/// (xyz) and its acceleration (w), and t in 0..1 the blend.
pub fn environment_gravity_with_centre(d: Vec4, centre: Vec4, t: f32, v2: Vec3) -> Vec3 {
    let towards = (centre.truncate() - v2).normalize_or_zero() * centre.w;
    (1.0 - t) * environment_gravity(d) + t * towards
}

/// Front gravity gF = ¼·|gE|·f: bends a blade over its front side rather than
/// straight down its own axis (paper eq. 3).
pub fn front_gravity(g_env: Vec3, front: Vec3) -> Vec3 {
    0.25 * g_env.length() * front
}

/// Total gravity g = gE + gF (paper eq. 4).
pub fn gravity(blade: &Blade, d: Vec4) -> Vec3 {
    gravity_from(blade, environment_gravity(d))
}

/// Total gravity g = gE + gF (paper eq. 4) for a given environment gravity `g_env`
/// (from [`environment_gravity`] or [`environment_gravity_with_centre`]).
pub fn gravity_from(blade: &Blade, g_env: Vec3) -> Vec3 {
    g_env + front_gravity(g_env, blade.front_dir())
}

/// The rest position of the tip, Iv2 = v0 + h·up (paper eq. 5).
pub fn rest_tip(blade: &Blade) -> Vec3 {
    blade.root() + blade.up_dir() * blade.height()
}

/// The recovery's rate s·max(1 − η, 0.1), η the collision strength: the recovery is
/// r = (Iv2 − v2)·rate (paper eq. 5).
pub fn recovery_rate(blade: &Blade, collision_strength: f32) -> f32 {
    blade.stiffness() * (1.0 - collision_strength).max(0.1)
}

/// Recovery r = (Iv2 − v2)·s·max(1 − η, 0.1): Hooke's law pulling the tip back to its
/// rest position Iv2 = v0 + h·up; η is the collision strength (paper eq. 5).
pub fn recovery(blade: &Blade, collision_strength: f32) -> Vec3 {
    (rest_tip(blade) - blade.tip()) * recovery_rate(blade, collision_strength)
}

/// Wind alignment fd = 1 − |normalize(wi) · normalize(v2 − v0)|: a blade whose axis
/// (root to tip) lies across the wind moves most, one whose axis points along the
/// wind least (paper eq. 7).
/// Zero wind gives alignment 1; the force is zero anyway.
pub fn wind_alignment(blade: &Blade, wind: Vec3) -> f32 {
    let along = (blade.tip() - blade.root()).normalize_or_zero();
    1.0 - wind.normalize_or_zero().dot(along).abs()
}

/// Height ratio fr = ((v2 − v0)·up)/h: a standing blade catches more wind than a
/// flattened one (paper eq. 8).
pub fn wind_height_ratio(blade: &Blade) -> f32 {
    (blade.tip() - blade.root()).dot(blade.up_dir()) / blade.height()
}

/// Wind force w = wi·fd·fr (paper eq. 9), `wind` being the field wi(v0, t).
pub fn wind_force(blade: &Blade, wind: Vec3) -> Vec3 {
    wind * wind_alignment(blade, wind) * wind_height_ratio(blade)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blade::Blade;

    fn close(a: Vec3, b: Vec3, eps: f32) -> bool {
        (a - b).length() < eps
    }

    /// A blade at the origin, up = +Y, θ = 0: t1 = +X, front f = up × t1 = −Z.
    fn blade() -> Blade {
        Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 10.0)
    }

    #[test]
    fn gravity_is_down_plus_a_quarter_towards_the_front() {
        let b = blade();
        assert!(close(b.front_dir(), -Vec3::Z, 1e-6));
        let g = gravity(&b, Vec4::new(0.0, -2.0, 0.0, 9.8));
        // gE = (0, −9.8, 0); gF = ¼·9.8·(0, 0, −1).
        assert!(close(g, Vec3::new(0.0, -9.8, -2.45), 1e-5));
    }

    #[test]
    fn recovery_is_zero_at_rest_and_hookean_when_bent() {
        let b = blade();
        assert!(close(recovery(&b, 0.0), Vec3::ZERO, 1e-6));
        let bent = b.with_curve(b.guide(), Vec3::new(1.0, 1.0, 0.0));
        // Iv2 − v2 = (0,2,0) − (1,1,0) = (−1, 1, 0); times s = 10.
        assert!(close(
            recovery(&bent, 0.0),
            Vec3::new(-10.0, 10.0, 0.0),
            1e-5
        ));
        // A fully trampled blade still recovers at 10 % strength.
        assert!(close(recovery(&bent, 1.5), Vec3::new(-1.0, 1.0, 0.0), 1e-5));
        assert!(close(recovery(&bent, 0.5), Vec3::new(-5.0, 5.0, 0.0), 1e-5));
    }

    #[test]
    fn wind_across_an_upright_blade_acts_fully() {
        let b = blade();
        let wi = Vec3::new(3.0, 0.0, 0.0);
        assert!((wind_alignment(&b, wi) - 1.0).abs() < 1e-6);
        assert!((wind_height_ratio(&b) - 1.0).abs() < 1e-6);
        assert!(close(wind_force(&b, wi), wi, 1e-6));
    }

    #[test]
    fn wind_along_the_blade_or_on_a_flat_blade_does_nothing() {
        let b = blade();
        // Wind straight up the blade axis: alignment 0.
        assert!(close(
            wind_force(&b, Vec3::new(0.0, 5.0, 0.0)),
            Vec3::ZERO,
            1e-6
        ));
        // Blade lying flat: height ratio 0.
        let flat = b.with_curve(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0));
        assert!(close(
            wind_force(&flat, Vec3::new(0.0, 0.0, 4.0)),
            Vec3::ZERO,
            1e-6
        ));
        // Half-bent blade at 45°, wind across the bend: fd = 1 − cos 45°, fr = 1/√2·|v2−v0|/h.
        let half = b.with_curve(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0));
        let wi = Vec3::new(2.0, 0.0, 0.0);
        let fd = 1.0 - core::f32::consts::FRAC_1_SQRT_2;
        let fr = 0.5;
        assert!(close(wind_force(&half, wi), wi * fd * fr, 1e-5));
    }

    #[test]
    fn gravity_centre_blends_between_direction_and_centre() {
        let d = Vec4::new(0.0, -1.0, 0.0, 9.8);
        let centre = Vec4::new(0.0, 0.0, -10.0, 4.0);
        let v2 = Vec3::new(0.0, 0.0, 0.0);
        assert_eq!(
            environment_gravity_with_centre(d, centre, 0.0, v2),
            Vec3::new(0.0, -9.8, 0.0)
        );
        assert!(
            (environment_gravity_with_centre(d, centre, 1.0, v2) - Vec3::new(0.0, 0.0, -4.0))
                .length()
                < 1e-6
        );
        let half = environment_gravity_with_centre(d, centre, 0.5, v2);
        assert!((half - Vec3::new(0.0, -4.9, -2.0)).length() < 1e-6);
        // A tip at the centre gets no pull from it, not NaN.
        assert!(environment_gravity_with_centre(d, centre, 1.0, centre.truncate()).is_finite());
    }

    #[test]
    fn zero_wind_and_zero_gravity_are_not_nan() {
        let b = blade();
        assert_eq!(wind_force(&b, Vec3::ZERO), Vec3::ZERO);
        assert_eq!(gravity(&b, Vec4::ZERO), Vec3::ZERO);
    }
}
