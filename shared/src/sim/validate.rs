//! State validation (paper section 5.2): after the forces move `v2`, keep the blade
//! above its ground, re-derive `v1` and restore its length, in this order.

use crate::Blade;
use spirv_std::glam::Vec3;

/// Step 1, v2 stays above the ground plane of its blade:
/// v2 ← v2 − up·min(up·(v2 − v0), 0).
pub fn keep_above_ground(v0: Vec3, up: Vec3, v2: Vec3) -> Vec3 {
    v2 - up * up.dot(v2 - v0).min(0.0)
}

/// Step 2, v1 from the tip's projected length lproj = |v2 − v0 − up·((v2 − v0)·up)|:
/// v1 = v0 + h·up·max(1 − lproj/h, 0.05·max(lproj/h, 1)).
/// A straight blade keeps v1 at the tip height; a flattened one lowers it, never below
/// 5 % of h, so v1 stays above v0.
pub fn guide_from_tip(v0: Vec3, up: Vec3, height: f32, v2: Vec3) -> Vec3 {
    let d = v2 - v0;
    let l_proj = (d - up * d.dot(up)).length();
    let ratio = l_proj / height;
    v0 + up * height * (1.0 - ratio).max(0.05 * ratio.max(1.0))
}

/// The paper's estimate of a Bezier curve's length, L = (2·L0 + (n − 1)·L1)/(n + 1)
/// with degree n = 2, i.e. (2·L0 + L1)/3, L0 = |v2 − v0| (the chord), L1 = |v2 − v1| +
/// |v1 − v0| (the control polygon).
pub fn paper_length(v0: Vec3, v1: Vec3, v2: Vec3) -> f32 {
    let l0 = (v2 - v0).length();
    let l1 = (v2 - v1).length() + (v1 - v0).length();
    (2.0 * l0 + l1) / 3.0
}

/// Step 3, length: the curve's length estimated by [`paper_length`], both segments
/// are scaled by r = h/L. Returns the corrected (v1, v2).
pub fn restore_length(v0: Vec3, v1: Vec3, v2: Vec3, height: f32) -> (Vec3, Vec3) {
    let r = height / paper_length(v0, v1, v2);
    let v1_new = v0 + r * (v1 - v0);
    let v2_new = v1_new + r * (v2 - v1);
    (v1_new, v2_new)
}

/// A blade whose tip is at least this fraction of its height h from its root counts as
/// bent; closer, the curve folds back on itself.
pub const BENT_REACH: f32 = 0.7;

/// Relative error |L − h|/h of the arc length L a validated bent blade may have. The
/// paper's estimate (2·L0 + L1)/3 is not the arc length: the worst bent shape, a tip
/// pushed straight down its own axis to 0.758·h, is 7.3 % short.
pub const LENGTH_TOLERANCE_BENT: f32 = 0.08;

/// Relative length error of any validated blade: a tip pushed straight down onto its
/// root folds the curve to 1.5·h (a limit of the paper's method, kept as such).
pub const LENGTH_TOLERANCE_FOLDED: f32 = 0.5;

/// All three steps, in the paper's order, on a blade whose `v2` the forces moved.
pub fn validate(blade: &Blade) -> Blade {
    let (v0, up, h) = (blade.root(), blade.up_dir(), blade.height());
    let v2 = keep_above_ground(v0, up, blade.tip());
    let v1 = guide_from_tip(v0, up, h, v2);
    let (v1, v2) = restore_length(v0, v1, v2, h);
    blade.with_curve(v1, v2)
}

/// Arc length of the quadratic Bezier curve (v0, v1, v2), by summing `segments`
/// chords: the exact reference the tests hold the estimate of step 3 against.
pub fn bezier_length(v0: Vec3, v1: Vec3, v2: Vec3, segments: u32) -> f32 {
    let mut length = 0.0;
    let mut prev = v0;
    let mut i = 1;
    while i <= segments {
        let t = i as f32 / segments as f32;
        let p = v0 * ((1.0 - t) * (1.0 - t)) + v1 * (2.0 * t * (1.0 - t)) + v2 * (t * t);
        length += (p - prev).length();
        prev = p;
        i += 1;
    }
    length
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Blade;

    fn close(a: Vec3, b: Vec3, eps: f32) -> bool {
        (a - b).length() < eps
    }

    #[test]
    fn tip_below_ground_is_lifted_onto_it() {
        let v2 = keep_above_ground(Vec3::ZERO, Vec3::Y, Vec3::new(1.0, -0.5, 2.0));
        assert!(close(v2, Vec3::new(1.0, 0.0, 2.0), 1e-6));
        // Above the ground nothing changes.
        let above = Vec3::new(1.0, 0.5, 2.0);
        assert_eq!(keep_above_ground(Vec3::ZERO, Vec3::Y, above), above);
        // On a tilted ground the plane is the blade's own.
        let up = Vec3::new(1.0, 1.0, 0.0).normalize();
        let v2 = keep_above_ground(Vec3::ONE, up, Vec3::ONE - up * 0.3 + Vec3::Z);
        assert!(up.dot(v2 - Vec3::ONE).abs() < 1e-6);
    }

    #[test]
    fn guide_hand_worked_cases() {
        // Upright tip: lproj = 0 → v1 = v0 + h·up.
        let v1 = guide_from_tip(Vec3::ZERO, Vec3::Y, 2.0, Vec3::new(0.0, 2.0, 0.0));
        assert!(close(v1, Vec3::new(0.0, 2.0, 0.0), 1e-6));
        // lproj = 1, h = 2: max(1 − 0.5, 0.05·1) = 0.5 → v1 = (0, 1, 0).
        let v1 = guide_from_tip(Vec3::ZERO, Vec3::Y, 2.0, Vec3::new(1.0, 1.5, 0.0));
        assert!(close(v1, Vec3::new(0.0, 1.0, 0.0), 1e-6));
        // lproj = 4 > h: max(1 − 2, 0.05·2) = 0.1 → v1 = (0, 0.2, 0), still above v0.
        let v1 = guide_from_tip(Vec3::ZERO, Vec3::Y, 2.0, Vec3::new(4.0, 0.0, 0.0));
        assert!(close(v1, Vec3::new(0.0, 0.2, 0.0), 1e-6));
    }

    #[test]
    fn length_estimate_hand_worked() {
        // Straight blade of length 4 with h = 2: L0 = L1 = 4, L = 4, r = ½.
        let (v1, v2) = restore_length(Vec3::ZERO, Vec3::Y * 2.0, Vec3::Y * 4.0, 2.0);
        assert!(close(v1, Vec3::Y, 1e-6) && close(v2, Vec3::Y * 2.0, 1e-6));
    }

    // The bounds are `LENGTH_TOLERANCE_BENT` and `LENGTH_TOLERANCE_FOLDED` (worst
    // seen on this grid: 7.3 % short, bent).

    #[test]
    fn validation_keeps_blades_above_ground_with_v1_above_v0_and_length_near_h() {
        let base = Blade::at_rest(Vec3::new(0.5, 0.0, -0.5), Vec3::Y, 1.0, 1.8, 0.12, 9.0);
        let (mut worst_bent, mut worst_any): (f32, f32) = (0.0, 0.0);
        // Tips pushed everywhere: far, near, sideways, under the ground.
        for ix in -8..=8 {
            for iy in -4..=8 {
                for iz in -8..=8 {
                    let push = Vec3::new(ix as f32, iy as f32, iz as f32) * 0.4;
                    let moved = base.with_curve(base.guide(), base.tip() + push);
                    let b = validate(&moved);
                    let (v0, up) = (b.root(), b.up_dir());
                    assert!(up.dot(b.tip() - v0) >= -1e-5, "v2 below ground: {b:?}");
                    assert!(up.dot(b.guide() - v0) > 0.0, "v1 not above v0: {b:?}");
                    let len = bezier_length(v0, b.guide(), b.tip(), 64);
                    let error = (len - b.height()).abs() / b.height();
                    worst_any = worst_any.max(error);
                    if (b.tip() - v0).length() >= BENT_REACH * b.height() {
                        worst_bent = worst_bent.max(error);
                    }
                }
            }
        }
        assert!(
            worst_bent < LENGTH_TOLERANCE_BENT,
            "bent: worst relative error {worst_bent}"
        );
        assert!(
            worst_any < LENGTH_TOLERANCE_FOLDED,
            "any: worst relative error {worst_any}"
        );
    }
}
