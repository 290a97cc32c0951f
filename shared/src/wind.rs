//! The wind field wi(v0, t): an analytic function of position and time (paper
//! section 5.1 leaves its form open).

use spirv_std::glam::{Vec3, Vec4};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// A steady breeze along `wind.xyz` (unit, in the ground plane) of strength `wind.w`,
/// modulated by waves travelling downwind and a weaker cross-wind ripple, so the field
/// sways instead of pushing every blade alike. |wi| ≤ 1.15·strength.
pub fn breeze(p: Vec3, time: f32, wind: Vec4) -> Vec3 {
    let dir = wind.truncate().normalize_or_zero();
    let strength = wind.w;
    // Horizontal axis across the wind (for dir = +X it is +Z).
    let across = Vec3::new(-dir.z, 0.0, dir.x);
    let along_phase = dir.dot(p) * 0.35 - time * 1.7;
    let across_phase = across.dot(p) * 0.9 + time * 2.3;
    // Gusts: 0.2 .. 1.0 of the strength, moving downwind.
    let gust = 0.6 + 0.4 * along_phase.sin() * (0.37 * along_phase + 0.5).cos();
    let ripple = 0.15 * across_phase.sin();
    (dir * gust + across * ripple) * strength
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn breeze_is_bounded_finite_and_changes_with_place_and_time() {
        let wind = Vec4::new(1.0, 0.0, 0.0, 4.0);
        let mut seen = Vec::new();
        for i in -20..20 {
            for t in 0..50 {
                let p = Vec3::new(i as f32 * 0.7, 0.0, i as f32 * -1.3);
                let w = breeze(p, t as f32 * 0.13, wind);
                assert!(w.is_finite());
                assert!(w.length() <= 1.15 * 4.0 + 1e-4);
                // Always blowing downwind (gust ≥ 0.2).
                assert!(w.x >= 0.2 * 4.0 - 1e-4);
                seen.push(w.x);
            }
        }
        let spread = seen.iter().cloned().fold(f32::MIN, f32::max)
            - seen.iter().cloned().fold(f32::MAX, f32::min);
        assert!(spread > 1.0, "the breeze should vary, spread {spread}");
    }

    #[test]
    fn calm_is_zero() {
        assert_eq!(breeze(Vec3::ONE, 3.0, Vec4::ZERO), Vec3::ZERO);
    }
}
