//! Leaves rounded across their width and lit through, ambient occlusion towards the
//! root, and the ground under the grass (Wohllaib, GDC 2021).

use super::{SKY_AMBIENT, SUN};
use spirv_std::glam::Vec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Rounding of the blade across its width: the normal turns by up to this angle
/// (radians) towards each edge.
pub const ROUNDING: f32 = 0.6;

/// The normal of a leaf rounded across its width: `normal` turned towards −t1 at
/// the edge u = 0 and towards +t1 at u = 1, by up to `ROUNDING` radians, so a blade
/// shades like a curved leaf, not a flat card (Ghost of Tsushima). Unit length.
pub fn rounded_normal(normal: Vec3, width_dir: Vec3, u: f32) -> Vec3 {
    let angle = (2.0 * u.clamp(0.0, 1.0) - 1.0) * ROUNDING;
    (normal * angle.cos() + width_dir * angle.sin()).normalize_or_zero()
}

/// Ambient occlusion of a blade at height `v` in a field of relative density
/// `density` (1: every blade kept, less where the distance test thins it): the
/// canopy hides the sky towards the root, 1 − 0.75·density·(1 − v)².
pub fn ambient_occlusion(v: f32, density: f32) -> f32 {
    let below = 1.0 - v.clamp(0.0, 1.0);
    1.0 - 0.75 * density.clamp(0.0, 1.0) * below * below
}

/// Light through a thin leaf: zero while the sun is on the viewer's side of the
/// blade (`facing` is the normal turned towards the viewer), growing as the sun
/// comes from behind it, strongest when the viewer looks into the sun.
pub fn translucency(facing: Vec3, to_light: Vec3, to_eye: Vec3) -> f32 {
    let behind = (-facing.dot(to_light)).max(0.0);
    let into_sun = (-to_eye.dot(to_light)).max(0.0);
    behind * (0.35 + 0.65 * into_sun * into_sun * into_sun * into_sun)
}

/// A soft specular highlight (Blinn-Phong, exponent 24, strength 0.1), zero on the
/// side away from the sun.
pub fn soft_specular(facing: Vec3, to_light: Vec3, to_eye: Vec3) -> f32 {
    if facing.dot(to_light) <= 0.0 {
        return 0.0;
    }
    let half = (to_light + to_eye).normalize_or_zero();
    // x²⁴ by squaring: x⁸ · x¹⁶.
    let x2 = facing.dot(half).max(0.0);
    let x2 = x2 * x2;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    0.1 * x8 * x8 * x8
}

/// The radiance of a leaf fragment: sky light times occlusion, sun light (direct,
/// through the leaf, specular) times the shadow factor `sun` (1 lit, 0 shadowed).
/// `normal` is either face; it is turned towards the viewer.
pub fn shade_leaf(
    albedo: Vec3,
    normal: Vec3,
    to_light: Vec3,
    to_eye: Vec3,
    occlusion: f32,
    sun: f32,
) -> Vec3 {
    let facing = if normal.dot(to_eye) < 0.0 {
        -normal
    } else {
        normal
    };
    let diffuse = facing.dot(to_light).max(0.0);
    let through = translucency(facing, to_light, to_eye);
    let sky = SKY_AMBIENT * (0.6 + 0.4 * facing.y.max(0.0)) * occlusion;
    let direct =
        albedo * (diffuse + 1.4 * through) + Vec3::splat(soft_specular(facing, to_light, to_eye));
    albedo * sky + SUN * direct * sun
}
