//! Hashes, value noise and `smoothstep`: the pseudo-random and blending functions
//! every part of the model draws on.

use spirv_std::glam::Vec2;

/// A 32-bit integer hash (Chris Wellons's `lowbias32`).
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Uniform in 0..1 from `x`.
pub fn hash_unit(x: u32) -> f32 {
    (hash_u32(x) >> 8) as f32 / 16_777_216.0
}

/// 0 below `a`, 1 above `b`, the cubic 3t² − 2t³ between.
pub fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn hash_grid(x: u32, y: u32) -> f32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2c1b_3c6d);
    h ^= h >> 12;
    (h & 0x00ff_ffff) as f32 / 16_777_216.0
}

/// Bilinear value noise in 0..1 on a unit grid.
pub fn value_noise(p: Vec2) -> f32 {
    let cell = p.floor();
    let f = p - cell;
    let s = f * f * (Vec2::splat(3.0) - 2.0 * f);
    let (x, y) = (cell.x as i32 as u32, cell.y as i32 as u32);
    let a = hash_grid(x, y);
    let b = hash_grid(x.wrapping_add(1), y);
    let c = hash_grid(x, y.wrapping_add(1));
    let d = hash_grid(x.wrapping_add(1), y.wrapping_add(1));
    let top = a + (b - a) * s.x;
    let bottom = c + (d - c) * s.x;
    top + (bottom - top) * s.y
}
