//! The sky with a sun disc, the meadow beyond the drawn field to the horizon,
//! aerial perspective (Quilez, *Better fog*, 2010) and the tone map (Narkowicz's ACES
//! fit, 2016).

use crate::draw::look::SUN;
use crate::noise::smoothstep;
use spirv_std::glam::Vec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Angular radius of the sun disc, radians (about 1.5× the real sun, so it reads).
pub const SUN_RADIUS: f32 = 0.012;

/// cos of [`SUN_RADIUS`] and of 1.2 times it, as constants (1 − x²/2, exact to f32
/// at these angles): a per-pixel cos costs a software device dearly.
pub(crate) const SUN_COS: (f32, f32) = (
    1.0 - 0.5 * SUN_RADIUS * SUN_RADIUS,
    1.0 - 0.72 * SUN_RADIUS * SUN_RADIUS,
);

/// Sky radiance towards `dir` (unit) with the sun towards `sun` (unit): a gradient
/// from a pale horizon to a deep zenith, a glow around the sun, the sun disc, and a
/// dim ground colour below the horizon: [`sky_gradient`] + [`sun_disc`].
pub fn sky(dir: Vec3, sun: Vec3) -> Vec3 {
    sky_gradient(dir, sun) + sun_disc(dir, sun)
}

/// The sky without its disc: smooth enough over the screen for the tone map to
/// evaluate it at the corners of a coarse grid and interpolate.
pub fn sky_gradient(dir: Vec3, sun: Vec3) -> Vec3 {
    let zenith = Vec3::new(0.16, 0.34, 0.78);
    let horizon = Vec3::new(0.62, 0.74, 0.92);
    let up = dir.y.max(0.0);
    let base = horizon.lerp(zenith, 1.0 - (1.0 - up) * (1.0 - up) * (1.0 - up));
    let below = Vec3::new(0.30, 0.32, 0.30).lerp(horizon, (1.0 + dir.y * 8.0).clamp(0.0, 1.0));
    let base = if dir.y < 0.0 { below } else { base };
    let cos = dir.dot(sun).clamp(-1.0, 1.0);
    // cos⁶ and cos⁶⁴ by squaring (a software device pays for powf per pixel).
    let c2 = cos.max(0.0) * cos.max(0.0);
    let c4 = c2 * c2;
    let c8 = c4 * c4;
    let c64 = c8 * c8 * c8 * c8 * c8 * c8 * c8 * c8;
    let glow = c64 * 0.6 + c4 * c2 * 0.12;
    base + SUN * glow / SUN.x
}

/// The sun disc alone (a few pixels wide: evaluated per pixel).
pub fn sun_disc(dir: Vec3, sun: Vec3) -> Vec3 {
    let cos = dir.dot(sun).clamp(-1.0, 1.0);
    SUN * (smoothstep(SUN_COS.1, SUN_COS.0, cos) * 40.0) / SUN.x
}

/// The sky without the sun disc, what fog takes on towards `dir`.
pub fn fog_colour(dir: Vec3, sun: Vec3) -> Vec3 {
    let horizon = Vec3::new(0.62, 0.74, 0.92);
    let cos = dir.dot(sun).max(0.0);
    let c2 = cos * cos;
    let c4 = c2 * c2;
    horizon + Vec3::new(0.9, 0.75, 0.5) * (c4 * c4 * 0.5)
}

/// Aerial perspective: `colour` at `distance` along `dir` fogged towards the sky,
/// 1 − exp(−density·distance) of the way.
pub fn fog(colour: Vec3, distance: f32, dir: Vec3, sun: Vec3, density: f32) -> Vec3 {
    let amount = 1.0 - (-density * distance.max(0.0)).exp();
    colour.lerp(fog_colour(dir, sun), amount)
}

/// Narkowicz's ACES fit per channel: x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14),
/// clamped to 0..1. Maps 0 to 0, increasing, 1 at about x = 11.
pub fn aces(x: f32) -> f32 {
    let x = x.max(0.0);
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// Linear HDR radiance to display-linear colour (the sRGB target encodes it):
/// `exposure` times the radiance through [`aces`].
pub fn tone_map(radiance: Vec3, exposure: f32) -> Vec3 {
    let x = radiance * exposure;
    Vec3::new(aces(x.x), aces(x.y), aces(x.z))
}
