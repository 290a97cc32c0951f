//! Sun shadows: a shadow map of two cascades (Dimitrov 2007), the far one fitted to the
//! shadowed region and the near one to the camera's surroundings, read with bilinear
//! percentage-closer filtering (Williams 1978; Reeves et al. 1987).

use crate::Blade;
use crate::blade::tangent_frame;
use spirv_std::glam::{Mat4, Vec3, Vec4};

/// The sun's shadow map: an orthographic view along −`to_sun` of the sphere
/// (`centre`, `radius`), depth 0..1 front to back (Vulkan).
pub fn sun_view_proj(to_sun: Vec3, centre: Vec3, radius: f32) -> Mat4 {
    let dir = to_sun.normalize_or_zero();
    let (side, _) = tangent_frame(dir);
    let up = dir.cross(side);
    let eye = centre + dir * (2.0 * radius);
    let forward = -dir;
    let far = 4.0 * radius;
    // Rows: x and y across the light's view scaled to ±1, z from the eye to `far`.
    let row = |axis: Vec3, scale: f32| (axis / scale).extend(-axis.dot(eye) / scale);
    Mat4::from_cols(
        row(side, radius),
        row(up, radius),
        row(forward, far),
        Vec4::W,
    )
    .transpose()
}

/// True when `blade` casts a shadow worth drawing: its root within `reach` of the
/// camera, and some of it (its root, midpoint or tip) inside the shadow map of
/// `view_proj` (the others cast no shadow anyone reads).
pub fn casts_shadow(view_proj: Mat4, blade: &Blade, camera: Vec3, reach: f32) -> bool {
    (blade.root() - camera).length_squared() <= reach * reach && in_shadow_map(view_proj, blade)
}

/// True when some of `blade` (its root, midpoint or tip) falls inside the shadow map
/// of `view_proj`.
pub fn in_shadow_map(view_proj: Mat4, blade: &Blade) -> bool {
    let inside = |p: Vec3| {
        let c = shadow_coord(view_proj, p);
        c.x >= 0.0 && c.x <= 1.0 && c.y >= 0.0 && c.y <= 1.0
    };
    inside(blade.root()) || inside(blade.midpoint()) || inside(blade.tip())
}

/// Tessellation level of a shadow caster: one segment (two triangles). Fixed, like
/// the rest of the caster, so that the shadows do not follow the camera's level of
/// detail either (a blade's `lod.fewest` is the camera's setting).
pub const CASTER_LEVEL: f32 = 1.0;

/// Casters one workgroup of the shadow map's compute rasterizer draws
/// (`compute::shadow::raster_casters`, `shadow_raster`): one a thread.
pub const CASTERS_PER_GROUP: u32 = 32;

/// The workgroups for `count` casters, [`CASTERS_PER_GROUP`] each
/// (`meshlet::group_grid`).
pub fn caster_grid(count: u32) -> spirv_std::glam::UVec3 {
    crate::draw::meshlet::group_grid(count.div_ceil(CASTERS_PER_GROUP))
}

/// Radius of the near cascade, in units: the shadows of the blades nearest the camera,
/// in texels four times finer than the far cascade's at its most reach (48 units).
pub const NEAR_REACH: f32 = 12.0;

/// The near cascade's sphere inside the far one (`far`, centre and radius): one of
/// [`NEAR_REACH`] around the camera, its centre snapped to a sixteenth of its radius so
/// it does not swim as the camera moves; the far sphere itself where that is no
/// larger.
pub fn near_sphere(far: (Vec3, f32), camera: Vec3) -> (Vec3, f32) {
    if far.1 <= NEAR_REACH {
        return far;
    }
    (snapped(camera, NEAR_REACH), NEAR_REACH)
}

/// `p` snapped to a grid of a sixteenth of `radius`: where a map of that radius
/// around a moving camera is centred, so it moves in steps and does not swim.
pub fn snapped(p: Vec3, radius: f32) -> Vec3 {
    let step = radius / 16.0;
    (p / step).round() * step
}

/// Where `p` falls in the two cascades' map (Dimitrov 2007, cascaded shadow maps): the
/// near cascade in the left half, the far one in the right, `size` texels a side
/// each; (u, v) over the whole map and the depth, and whether it falls on either.
/// The near cascade is read where `p` lies more than a texel and a half inside it, so
/// the four texels the filter reads never cross into the other half.
pub fn cascade_coord(near: Mat4, far: Mat4, p: Vec3, size: u32) -> (bool, Vec3) {
    let margin = 1.5 / size as f32;
    let inside = |c: Vec3| {
        c.x > margin && c.y > margin && c.x < 1.0 - margin && c.y < 1.0 - margin && c.z < 1.0
    };
    let c = shadow_coord(near, p);
    if inside(c) {
        return (true, Vec3::new(0.5 * c.x, c.y, c.z));
    }
    let c = shadow_coord(far, p);
    (inside(c), Vec3::new(0.5 + 0.5 * c.x, c.y, c.z))
}

/// Where `p` falls in the shadow map: (u, v) in 0..1 and its depth, from the map's
/// `view_proj`.
pub fn shadow_coord(view_proj: Mat4, p: Vec3) -> Vec3 {
    let clip: Vec4 = view_proj * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    Vec3::new(0.5 * ndc.x + 0.5, 0.5 * ndc.y + 0.5, ndc.z)
}

/// True when a shadow coordinate (`shadow_coord`) falls on the map: outside it
/// everything is lit.
pub fn on_shadow_map(coord: Vec3) -> bool {
    coord.x > 0.0 && coord.y > 0.0 && coord.x < 1.0 && coord.y < 1.0 && coord.z < 1.0
}

/// The depth bias of a shadow lookup in a map of `size` texels: two texels' worth of
/// depth (the map is 4 radii deep and 2 radii wide).
pub fn shadow_bias(size: u32) -> f32 {
    2.0 / size as f32
}

/// Share of the four nearest texels (bilinear weights) whose stored depth is at or
/// behind `depth − bias`: 1 lit, 0 in shadow. `texel(x, y)` reads the map, `size`
/// texels a side; outside the map everything is lit. This is what the shaders' one
/// fetch through a comparison sampler (compare op LESS_OR_EQUAL, linear filter)
/// computes in the texture unit; the host runs it here.
pub fn shadow_factor(coord: Vec3, size: u32, bias: f32, texel: impl Fn(i32, i32) -> f32) -> f32 {
    if !on_shadow_map(coord) {
        return 1.0;
    }
    let p = Vec3::new(
        coord.x * size as f32 - 0.5,
        coord.y * size as f32 - 0.5,
        0.0,
    );
    let base = p.floor();
    let f = p - base;
    let (x, y) = (base.x as i32, base.y as i32);
    let max = size as i32 - 1;
    let lit = |dx: i32, dy: i32| {
        let d = texel((x + dx).clamp(0, max), (y + dy).clamp(0, max));
        if coord.z - bias <= d { 1.0 } else { 0.0 }
    };
    let top = lit(0, 0) * (1.0 - f.x) + lit(1, 0) * f.x;
    let bottom = lit(0, 1) * (1.0 - f.x) + lit(1, 1) * f.x;
    top * (1.0 - f.y) + bottom * f.y
}
