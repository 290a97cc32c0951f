//! The natural look shaded after the draw (a visibility buffer: Burns and Hunt, *The
//! Visibility Buffer: A Cache-Friendly Approach to Deferred Shading*, JCGT 2013): at
//! one sample per pixel the grass's fragment stage writes only which blade covers the
//! pixel and where on it (its slot among the dressed blades, its surface coordinates
//! u across and v along), packed into the HDR colour it would have shaded; a compute
//! pass then shades each such pixel once from the blade itself
//! (`compute::shade::shade_natural`). The packing is marked by a negative alpha,
//! which nothing else draws (the ground, stones and far blades write an alpha of 0
//! to 1 over it, the clear is 0), so what is drawn over a blade replaces its mark.
//!
//! Why: on the NVIDIA H100 only a few of the SMs run fragment stages, so a pixel
//! shaded in a compute pass costs a fraction of one shaded by the fragment stage,
//! and the blade's own motion (temporal anti-aliasing) comes from the same
//! evaluation instead of a second colour target.
//!
//! Every field is an integer of at most 12 bits offset to −2048..2047, which a half
//! float (11 significant bits and a sign) holds exactly.

use spirv_std::glam::{Vec2, Vec4};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Slots the packing can name: 24 bits, in the red and green halves.
pub const SLOTS: u32 = 1 << 24;

/// Steps of u across the blade (12 bits, in the blue half).
const U_STEPS: f32 = 4095.0;
/// Steps of v along the blade (11 bits, in the alpha half as −1 − v·2047).
const V_STEPS: f32 = 2047.0;
/// The offset that centres a 12-bit field on zero.
const OFFSET: f32 = 2048.0;

/// The packed visibility of the blade in `slot` (below [`SLOTS`]) at surface
/// coordinates `uv` (each 0..1, clamped): red and green the slot's low and high 12
/// bits, blue u to 1/4095, alpha −1 − v·2047 (negative: the mark).
pub fn pack(slot: u32, uv: Vec2) -> Vec4 {
    let uv = uv.clamp(Vec2::ZERO, Vec2::ONE);
    Vec4::new(
        (slot & 0xfff) as f32 - OFFSET,
        ((slot >> 12) & 0xfff) as f32 - OFFSET,
        (uv.x * U_STEPS).round() - OFFSET,
        -1.0 - (uv.y * V_STEPS).round(),
    )
}

/// Whether a drawn `texel` holds a blade's [`pack`]ed visibility (negative alpha)
/// rather than a colour.
pub fn is_packed(texel: Vec4) -> bool {
    texel.w < 0.0
}

/// The (slot, uv) a [`pack`]ed `texel` names.
pub fn unpack(texel: Vec4) -> (u32, Vec2) {
    let low = (texel.x + OFFSET).round() as u32;
    let high = (texel.y + OFFSET).round() as u32;
    let u = (texel.z + OFFSET).round() / U_STEPS;
    let v = (-1.0 - texel.w).round() / V_STEPS;
    (low | (high << 12), Vec2::new(u, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rounds each value through a half float, as the HDR target stores it.
    fn through_half(v: Vec4) -> Vec4 {
        let h = |x: f32| half_round_trip(x);
        Vec4::new(h(v.x), h(v.y), h(v.z), h(v.w))
    }

    /// `x` rounded to the nearest half float (11 significant bits), for values well
    /// inside the half range.
    fn half_round_trip(x: f32) -> f32 {
        if x == 0.0 {
            return 0.0;
        }
        let exponent = x.abs().log2().floor();
        let step = 2f32.powf(exponent - 10.0);
        (x / step).round() * step
    }

    /// Every slot's bits and the extremes of u and v come back exactly through a
    /// half-float target; the mark is negative for every packing.
    #[test]
    fn packing_survives_half_floats() {
        let slots = [
            0,
            1,
            2047,
            2048,
            4095,
            4096,
            0x12_3456,
            SLOTS / 2,
            SLOTS - 1,
        ];
        let uvs = [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (0.5, 0.25)];
        for slot in slots {
            for (u, v) in uvs {
                let packed = through_half(pack(slot, Vec2::new(u, v)));
                assert!(is_packed(packed), "{slot} {u} {v}: {packed}");
                let (s, uv) = unpack(packed);
                assert_eq!(s, slot);
                assert!((uv.x - u).abs() <= 0.5 / U_STEPS + 1e-6, "u {u}: {}", uv.x);
                assert!((uv.y - v).abs() <= 0.5 / V_STEPS + 1e-6, "v {v}: {}", uv.y);
            }
        }
    }

    /// u and v come back to within half a step everywhere (hand-worked: v = 0.3 is
    /// step 614.1 → 614, 614/2047 = 0.29995), and out-of-range coordinates clamp.
    #[test]
    fn surface_coordinates_round_to_their_steps() {
        let (_, uv) = unpack(through_half(pack(7, Vec2::new(0.3, 0.3))));
        assert!((uv.y - 614.0 / 2047.0).abs() < 1e-6, "{}", uv.y);
        assert!((uv.x - 1229.0 / 4095.0).abs() < 1e-6, "{}", uv.x);
        for k in 0..=1000 {
            let t = k as f32 / 1000.0;
            let (_, uv) = unpack(through_half(pack(9, Vec2::new(t, 1.0 - t))));
            assert!((uv.x - t).abs() <= 0.5 / U_STEPS + 1e-6, "u {t}: {}", uv.x);
            assert!((uv.y - (1.0 - t)).abs() <= 0.5 / V_STEPS + 1e-6);
        }
        let (_, uv) = unpack(pack(3, Vec2::new(-0.2, 1.3)));
        assert_eq!(uv, Vec2::new(0.0, 1.0));
    }

    /// What the other passes write is never taken for a blade: a colour's alpha is
    /// 0 (the clear, the sky) to 1.
    #[test]
    fn colours_are_not_packed() {
        for alpha in [0.0, 0.5, 1.0] {
            assert!(!is_packed(Vec4::new(0.2, 0.3, 0.1, alpha)));
        }
        assert!(!is_packed(Vec4::ZERO));
    }
}
