//! Shading of the fragment stages: Lambert plus ambient, blades lit on both faces.

use crate::noise::value_noise;
use spirv_std::glam::{Vec2, Vec3};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Grass view: shaded blades.
pub const VIEW_SHADED: u32 = 0;
/// Grass view: blades coloured by tessellation level.
pub const VIEW_LOD: u32 = 1;
/// Grass view: shaded wireframe of the tessellated blades.
pub const VIEW_WIREFRAME: u32 = 2;

/// Blade colour at the root (linear RGB).
pub const BLADE_BASE: Vec3 = Vec3::new(0.02, 0.10, 0.01);
/// Blade colour at the tip (linear RGB).
pub const BLADE_TIP: Vec3 = Vec3::new(0.30, 0.55, 0.08);

/// The sun: one directional light and an ambient term.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Light {
    /// Unit direction towards the light.
    pub direction: Vec3,
    /// Ambient share of the light, 0 to 1.
    pub ambient: f32,
}

/// Lambert with ambient: albedo·(ambient + (1 − ambient)·max(n·l, 0)).
pub fn lambert(albedo: Vec3, normal: Vec3, light: Light) -> Vec3 {
    let diffuse = normal.dot(light.direction).max(0.0);
    albedo * (light.ambient + (1.0 - light.ambient) * diffuse)
}

/// The normal of the face the viewer sees: `normal` on its front, else the opposite.
pub fn facing_normal(normal: Vec3, front: bool) -> Vec3 {
    if front { normal } else { -normal }
}

/// A blade fragment at height `v` (0 root, 1 tip) whose normal `facing` is turned
/// towards the viewer ([`facing_normal`]), so both faces of the thin blade are lit:
/// the base-to-tip gradient, lit by Lambert.
pub fn shade_facing(facing: Vec3, light: Light, v: f32) -> Vec3 {
    lambert(BLADE_BASE.lerp(BLADE_TIP, v), facing, light)
}

/// [`shade_facing`] for a blade of `species` (`crate::species`): its head in the
/// species' colour (`species::albedo`).
pub fn shade_species(facing: Vec3, light: Light, v: f32, species: u32) -> Vec3 {
    let gradient = BLADE_BASE.lerp(BLADE_TIP, v);
    lambert(
        crate::species::albedo(species, gradient, v, 1.0),
        facing,
        light,
    )
}

/// [`shade_species`] at a height tagged with its species (`species::tag_v`, the
/// paper look's geometry stages' varying).
pub fn shade_tagged(facing: Vec3, light: Light, tagged_v: f32) -> Vec3 {
    // Grass (tagged below 2) is shaded as the paper shades it, at no extra cost.
    if tagged_v < 2.0 {
        return shade_facing(facing, light, tagged_v);
    }
    let (v, species) = crate::species::untag_v(tagged_v);
    shade_species(facing, light, v, species)
}

/// [`shade_facing`] for a blade fragment at `position` seen from `camera`, its normal
/// turned towards the camera.
pub fn shade_blade(normal: Vec3, position: Vec3, camera: Vec3, light: Light, v: f32) -> Vec3 {
    let front = normal.dot(camera - position) >= 0.0;
    shade_facing(facing_normal(normal, front), light, v)
}

/// Debug colour of a tessellation level: blue at level 1, through green, to red at
/// [`MAX_LEVEL`](crate::cull::lod::MAX_LEVEL), shaded like a blade so the shape still reads.
pub fn lod_colour(level: f32) -> Vec3 {
    let t = ((level - 1.0) / (crate::cull::lod::MAX_LEVEL - 1.0)).clamp(0.0, 1.0);
    let blue = Vec3::new(0.05, 0.15, 1.0);
    let green = Vec3::new(0.1, 0.9, 0.1);
    let red = Vec3::new(1.0, 0.08, 0.02);
    if t < 0.5 {
        blue.lerp(green, 2.0 * t)
    } else {
        green.lerp(red, 2.0 * t - 1.0)
    }
}

/// What the grass fragment stage shows (see `VIEW_*`): the shaded blade, its normal
/// `facing` the viewer ([`facing_normal`]).
pub fn blade_colour(view: u32, facing: Vec3, light: Light, v: f32, level: f32) -> Vec3 {
    if view == VIEW_LOD {
        lod_shade(facing, light, v, level)
    } else {
        shade_facing(facing, light, v)
    }
}

/// The LOD view's colour of a blade fragment: the hue of its tessellation `level`,
/// with the blade's own light and gradient as brightness.
pub fn lod_shade(facing: Vec3, light: Light, v: f32, level: f32) -> Vec3 {
    // The paper look's v carries the blade's species (`species::tag_v`).
    let (v, _) = crate::species::untag_v(v);
    let brightness = shade_facing(facing, light, v).length() / BLADE_TIP.length();
    lod_colour(level) * (0.35 + 0.65 * brightness.min(1.0))
}

/// sRGB-encoded value to linear (the overlay's vertex colours are sRGB).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear value to sRGB-encoded (what an sRGB image stores; IEC 61966-2-1), the
/// inverse of [`srgb_to_linear`]: the embedding example encodes its host tone map so.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The ground's texture, generated: soil with patches of two noise octaves.
pub fn ground_albedo(xz: Vec2) -> Vec3 {
    let n = 0.65 * value_noise(xz * 1.7) + 0.35 * value_noise(xz * 7.3);
    let soil = Vec3::new(0.16, 0.10, 0.05);
    let moss = Vec3::new(0.07, 0.11, 0.03);
    soil.lerp(moss, n) * (0.7 + 0.6 * value_noise(xz * 23.0))
}

/// Material of a surface vertex: soil that grass grows on.
pub const MATERIAL_SOIL: u32 = 0;
/// Material of a surface vertex: bare rock.
pub const MATERIAL_ROCK: u32 = 1;
/// Material of a surface vertex: the collider ball.
pub const MATERIAL_BALL: u32 = 2;

/// Soil on a surface of any orientation: [`ground_albedo`] projected along the three
/// axes and blended by the normal (triplanar), so slopes and a planet's sides are
/// textured without stretching.
///
/// An axis whose weight is below [`TRIPLANAR_SKIP`] is not sampled (the others share
/// its weight): flat ground pays for one projection, not three, which matters where
/// fragment stages are scarce (the NVIDIA H100 shades graphics on few SMs).
pub fn soil_albedo(p: Vec3, n: Vec3) -> Vec3 {
    let w = n.abs() * n.abs();
    let w = w * w;
    let w = w / (w.x + w.y + w.z).max(1e-6);
    let w = Vec3::select(w.cmpge(Vec3::splat(TRIPLANAR_SKIP)), w, Vec3::ZERO);
    let w = w / (w.x + w.y + w.z).max(1e-6);
    let mut albedo = Vec3::ZERO;
    if w.x > 0.0 {
        albedo += ground_albedo(Vec2::new(p.z, p.y)) * w.x;
    }
    if w.y > 0.0 {
        albedo += ground_albedo(Vec2::new(p.x, p.z)) * w.y;
    }
    if w.z > 0.0 {
        albedo += ground_albedo(Vec2::new(p.x, p.y)) * w.z;
    }
    albedo
}

/// Triplanar weights below this are dropped by [`soil_albedo`]: a second projection is
/// sampled from about 17.6° of tilt (tan⁴θ = 0.01 / 0.99).
pub const TRIPLANAR_SKIP: f32 = 0.01;

/// Albedo of `material` at `p` with normal `n`.
pub fn surface_albedo(material: u32, p: Vec3, n: Vec3) -> Vec3 {
    match material {
        MATERIAL_ROCK => {
            let grain = 0.5 * value_noise(Vec2::new(p.x + p.y, p.z) * 3.1)
                + 0.5 * value_noise(Vec2::new(p.x, p.z - p.y) * 11.0);
            Vec3::new(0.22, 0.21, 0.2) * (0.7 + 0.6 * grain)
        }
        MATERIAL_BALL => Vec3::new(0.65, 0.12, 0.04),
        _ => soil_albedo(p, n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lod_colours_run_from_blue_to_red() {
        let lo = lod_colour(1.0);
        let mid = lod_colour(0.5 * (1.0 + crate::cull::lod::MAX_LEVEL));
        let hi = lod_colour(crate::cull::lod::MAX_LEVEL);
        assert!(lo.z > lo.x && lo.z > lo.y, "{lo}");
        assert!(mid.y > mid.x && mid.y > mid.z, "{mid}");
        assert!(hi.x > hi.y && hi.x > hi.z, "{hi}");
        // Clamped outside the range.
        assert_eq!(lod_colour(-5.0), lo);
        assert_eq!(lod_colour(100.0), hi);
    }

    #[test]
    fn srgb_conversion_at_known_points() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // sRGB 0.5 is linear 0.214.
        assert!((srgb_to_linear(0.5) - 0.214).abs() < 1e-3);
        assert!((linear_to_srgb(0.214) - 0.5).abs() < 1e-3);
        assert_eq!(linear_to_srgb(0.0), 0.0);
        // Each the other's inverse, on both sides of the linear toe.
        for c in [0.001, 0.003, 0.01, 0.2, 0.7, 1.0] {
            assert!((srgb_to_linear(linear_to_srgb(c)) - c).abs() < 1e-5, "{c}");
        }
    }

    #[test]
    fn lambert_hand_worked() {
        let light = Light {
            direction: Vec3::Y,
            ambient: 0.2,
        };
        assert_eq!(lambert(Vec3::ONE, Vec3::Y, light), Vec3::ONE);
        assert_eq!(lambert(Vec3::ONE, -Vec3::Y, light), Vec3::splat(0.2));
    }

    #[test]
    fn both_faces_are_lit() {
        let light = Light {
            direction: Vec3::Z,
            ambient: 0.1,
        };
        let cam = Vec3::new(0.0, 0.0, 5.0);
        let front = shade_blade(Vec3::Z, Vec3::ZERO, cam, light, 0.5);
        let back = shade_blade(-Vec3::Z, Vec3::ZERO, cam, light, 0.5);
        assert_eq!(front, back);
        assert!(shade_blade(Vec3::Z, Vec3::ZERO, cam, light, 1.0).y > front.y);
    }

    #[test]
    fn soil_on_flat_ground_is_the_ground_texture_and_rock_differs() {
        let p = Vec3::new(1.3, 0.0, -2.7);
        let flat = soil_albedo(p, Vec3::Y);
        assert!((flat - ground_albedo(Vec2::new(p.x, p.z))).length() < 1e-6);
        // A slope blends finite, in-range colours; a zero normal does not give NaN.
        let slope = soil_albedo(p, Vec3::new(0.6, 0.8, 0.0));
        assert!(slope.is_finite() && slope.max_element() < 1.0 && slope.min_element() >= 0.0);
        assert!(soil_albedo(p, Vec3::ZERO).is_finite());
        let rock = surface_albedo(MATERIAL_ROCK, p, Vec3::Y);
        assert!((rock - flat).length() > 0.05);
        assert_eq!(surface_albedo(MATERIAL_SOIL, p, Vec3::Y), flat);
        // Below 17.6° of tilt only the flat projection is sampled; at 45° the two
        // projections share the colour equally.
        let (s, c) = 15f32.to_radians().sin_cos();
        assert_eq!(soil_albedo(p, Vec3::new(s, c, 0.0)), flat);
        let (s, c) = 20f32.to_radians().sin_cos();
        assert_ne!(soil_albedo(p, Vec3::new(s, c, 0.0)), flat);
        let half = std::f32::consts::FRAC_1_SQRT_2;
        let side = ground_albedo(Vec2::new(p.z, p.y));
        let blend = soil_albedo(p, Vec3::new(half, half, 0.0));
        assert!((blend - 0.5 * (flat + side)).length() < 1e-6, "{blend}");
    }

    #[test]
    fn noise_is_in_range_and_continuous() {
        for i in -50..50 {
            let p = Vec2::new(i as f32 * 0.37, i as f32 * -0.61);
            let n = value_noise(p);
            assert!((0.0..=1.0).contains(&n));
            assert!((value_noise(p + Vec2::splat(1e-4)) - n).abs() < 1e-2);
        }
    }
}
