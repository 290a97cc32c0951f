//! The ground in the natural look: lit like a leaf's sky and sun, darkened and
//! tinted under the grass, and beyond the drawn field the meadow's colour to the
//! horizon, so the field has no edge.

use super::clump::{Clump, blade_albedo, palette};
use super::sky::fog;
use super::{LookParams, SKY_AMBIENT, SUN};
use crate::noise::smoothstep;
use spirv_std::glam::{Vec3, Vec4};

/// A ground fragment: Lambert under the sky and the sun.
pub fn shade_ground(albedo: Vec3, normal: Vec3, to_light: Vec3, occlusion: f32, sun: f32) -> Vec3 {
    let diffuse = normal.dot(to_light).max(0.0);
    albedo * (SKY_AMBIENT * occlusion * (0.6 + 0.4 * normal.y.max(0.0)) + SUN * diffuse * sun)
}

/// The soil under grass takes the colour of the grass's roots, and beyond where
/// blades thin out (from half `field_distance` on) the colour of the field seen from
/// afar, so the meadow seems to reach the horizon: `soil` blended to the clump's
/// colour by `cover` (0..1, 1 under grass).
pub fn ground_under_grass(soil: Vec3, clump: &Clump, distance: f32, field_distance: f32) -> Vec3 {
    let tint = palette(clump.dryness * 0.8);
    let roots = blade_albedo(tint, 0.0) * 0.7;
    let t = smoothstep(0.35 * field_distance, field_distance, distance);
    soil.lerp(roots, 0.75)
        .lerp(field_from_afar(0.2 + 0.6 * clump.dryness), t)
}

/// The field seen from afar: blades seen from the side cover the ground, so its
/// colour is their mid-height albedo, dimmed by the canopy's occlusion.
pub fn field_from_afar(dryness: f32) -> Vec3 {
    blade_albedo(palette(dryness * 0.8), 0.6) * 0.8
}

/// The meadow beyond the drawn field (natural look, ground scenes): where the view
/// ray from `camera` along `dir` meets the plane y = `ground.x`, the field's colour
/// from afar ([`field_from_afar`], its dryness from value noise over the clump size
/// `ground.z` as on the drawn ground), lit by sky and sun, fogged with density
/// `ground.y`. `None` when `ground.w` is 0 or the ray does not go down to the plane.
pub fn meadow_to_horizon(camera: Vec3, dir: Vec3, sun: Vec3, ground: Vec4) -> Option<Vec3> {
    use crate::noise::value_noise;
    use spirv_std::glam::Vec2;
    let below = camera.y - ground.x;
    if ground.w == 0.0 || dir.y >= -1e-4 || below <= 0.0 {
        return None;
    }
    let distance = below / -dir.y;
    let p = camera + dir * distance;
    let q = Vec2::new(p.x, p.z) / ground.z.max(1e-3) + 17.0;
    let albedo = field_from_afar(0.2 + 0.6 * value_noise(q));
    // The canopy seen from above the ground: the sky light and sun the blades' own
    // occlusion and shadows leave (what the drawn field shows on average).
    let lit = shade_ground(albedo, Vec3::Y, sun, 0.45, 0.55);
    Some(fog(lit, distance, dir, sun, ground.y))
}

/// The tone map's `ground` vector of [`meadow_to_horizon`] from the look's block.
pub fn horizon_ground(look: &LookParams) -> Vec4 {
    Vec4::new(
        look.ground_level,
        look.fog_density,
        look.clump_size,
        look.ground_to_horizon as f32,
    )
}

/// The natural look's ground: (albedo, sky occlusion) of `material` at `p` with normal
/// `n`, `distance` from the camera. Soil is the grass's ground: one octave of the soil
/// texture (cheaper than the paper look's three) under the roots' colour, the
/// field's colour far away ([`ground_under_grass`]), occluded by the canopy. The
/// clump colour here is value noise over the clump size, not the clumps' Voronoi
/// cells: 27 cells per pixel would cost more than the ground is allowed.
pub fn natural_ground(
    material: u32,
    p: Vec3,
    n: Vec3,
    distance: f32,
    look: &LookParams,
) -> (Vec3, f32) {
    use crate::draw::shade::{MATERIAL_SOIL, surface_albedo};
    use crate::noise::value_noise;
    use spirv_std::glam::Vec2;
    if material != MATERIAL_SOIL {
        return (surface_albedo(material, p, n), 1.0);
    }
    // The plane across the normal's dominant axis, so slopes and a planet get it too.
    let a = n.abs();
    let q = if a.y >= a.x && a.y >= a.z {
        Vec2::new(p.x, p.z)
    } else if a.x >= a.z {
        Vec2::new(p.z, p.y)
    } else {
        Vec2::new(p.x, p.y)
    };
    let soil = Vec3::new(0.16, 0.10, 0.05) * (0.7 + 0.6 * value_noise(q * 1.7));
    let clump = Clump {
        lean: Vec3::ZERO,
        height: 1.0,
        dryness: value_noise(q / look.clump_size.max(1e-3) + 17.0),
    };
    let albedo = ground_under_grass(soil, &clump, distance, look.field_distance);
    // Under the canopy the ground sees little sky; from afar, the field's colour
    // already holds its occlusion.
    let open = smoothstep(0.35 * look.field_distance, look.field_distance, distance);
    (albedo, 0.45 + 0.55 * open)
}
