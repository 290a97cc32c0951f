//! The natural look: what games add to the paper's Lambert blades. Clumps
//! and a colour palette, leaves rounded across their width and lit through, ambient
//! occlusion towards the root, fades instead of popping, a sky with a sun disc,
//! aerial perspective, sun shadows and a tone map. Every function here runs in the
//! shaders and in the host tests; `--look paper` skips all of it.
//!
//! Sources: clumps as Voronoi cells with shared lean, height and colour, rounded
//! normals and translucency follow Eric Wohllaib's *Procedural Grass in Ghost of
//! Tsushima* (GDC 2021); the sky gradient and exponential fog follow Iñigo Quilez's
//! *Better fog* (2010); the tone map is Krzysztof Narkowicz's fit of the ACES
//! reference rendering transform (2016).

use crate::Blade;
use crate::blade::tangent_frame;
use spirv_std::glam::{Mat4, Vec3, Vec4};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Look: the paper's Lambert blades, as before (the reference images).
pub const LOOK_PAPER: u32 = 0;
/// Look: clumps, colour, rounded lit leaves, shadows, sky, fog and tone mapping.
pub const LOOK_NATURAL: u32 = 1;

/// The natural look's values, as the frame block carries them.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LookParams {
    /// World to the sun's shadow map (clip space, depth 0..1).
    pub shadow_view_proj: Mat4,
    /// `LOOK_PAPER` or `LOOK_NATURAL`.
    pub style: u32,
    /// Shadows on (1) or off (0).
    pub shadows: u32,
    /// The field's seed: clumps and colours follow it.
    pub seed: u32,
    /// Side of the shadow map in texels (filled in by the renderer, which made it).
    pub shadow_size: u32,
    /// Fog density per unit of distance (aerial perspective).
    pub fog_density: f32,
    /// Where the distance test leaves no blade: the ground takes the field's colour
    /// towards it.
    pub field_distance: f32,
    /// Size of a pixel at distance 1 (2·tan(fov/2)/height): blades are kept at least
    /// this wide times their distance, and fade instead.
    pub pixel_angle: f32,
    /// Clump size in scene units.
    pub clump_size: f32,
    /// Farthest a blade casts a shadow from the camera (beyond, its shadow is a few
    /// pixels of a few pixels' blade).
    pub caster_distance: f32,
    /// Padding to 16 bytes.
    pub padding: [u32; 3],
    /// Samples per pixel of the frame (the renderer picks its targets from it).
    pub samples: u32,
    /// Factor on the radiance before the tone map.
    pub exposure: f32,
    /// Height of the ground plane that carries the field to the horizon.
    pub ground_level: f32,
    /// 1 where the scene is a ground under a sky (not a planet): below the horizon
    /// the tone map draws the field from afar on the plane at `ground_level`.
    pub ground_to_horizon: u32,
}

/// Sun radiance (linear, before exposure).
pub const SUN: Vec3 = Vec3::new(2.6, 2.45, 2.2);
/// Sky light on a surface facing up (linear, before exposure).
pub const SKY_AMBIENT: Vec3 = Vec3::new(0.42, 0.55, 0.75);

// ---- hashing -------------------------------------------------------------------

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

fn hash_cell(x: i32, y: i32, z: i32, seed: u32) -> u32 {
    hash_u32(
        (x as u32).wrapping_mul(0x8da6_b343)
            ^ (y as u32).wrapping_mul(0xd816_3841)
            ^ (z as u32).wrapping_mul(0xcb1a_b31f)
            ^ hash_u32(seed),
    )
}

// ---- clumps --------------------------------------------------------------------

/// What a clump gives its blades.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Clump {
    /// Lean: the blade tips move this far sideways per unit of height (a vector in
    /// world space, any length; only its part across `up` counts).
    pub lean: Vec3,
    /// Factor on the blades' height.
    pub height: f32,
    /// Dryness 0 (fresh) to 1 (dry), picks the colour from [`palette`].
    pub dryness: f32,
}

impl Clump {
    /// The clump as one `vec4` of the clump buffer: lean (x, z), height, dryness.
    /// The lean is horizontal (its y part is dropped; blades lean across their own
    /// `up` only, see [`dressed_blade`]).
    pub fn pack(&self) -> Vec4 {
        Vec4::new(self.lean.x, self.lean.z, self.height, self.dryness)
    }

    /// The clump of [`Clump::pack`].
    pub fn unpack(v: Vec4) -> Self {
        Self {
            lean: Vec3::new(v.x, 0.0, v.y),
            height: v.z,
            dryness: v.w,
        }
    }
}

/// Sharpness of the blend between clumps: weights fall by e per 1/`CLUMP_SHARPNESS`
/// cell sizes of extra distance, so a clump's inside is its own and its borders blend.
pub const CLUMP_SHARPNESS: f32 = 9.0;

/// The clump at `p`: Voronoi cells of jittered points on a 3D grid of `size` (so
/// any surface, a planet's included, has clumps), each cell's lean, height and
/// dryness from a hash of the cell and `seed`, blended with weights exp(−k·(dᵢ − d₁))
/// over the 27 neighbouring cells (k = [`CLUMP_SHARPNESS`] / size). The weights are
/// continuous in `p`, so the clumps blend at their borders without seams.
pub fn clump_at(p: Vec3, size: f32, seed: u32) -> Clump {
    let q = p / size.max(1e-4);
    let cell = q.floor();
    let (cx, cy, cz) = (cell.x as i32, cell.y as i32, cell.z as i32);
    // exp(−k·(dᵢ − d₁)) / Σ = exp(−k·dᵢ) / Σ: one pass, no nearest distance first. The
    // nearest feature is within 1.5 cells, so its weight (at least e^−13.5) never
    // underflows.
    let mut total = 0.0;
    let mut lean = Vec3::ZERO;
    let mut height = 0.0;
    let mut dryness = 0.0;
    let mut z = -1;
    while z <= 1 {
        let mut y = -1;
        while y <= 1 {
            let mut x = -1;
            while x <= 1 {
                let h = hash_cell(cx + x, cy + y, cz + z, seed);
                let d = (feature(cell, x, y, z, h) - q).length();
                let w = (-CLUMP_SHARPNESS * d).exp();
                let angle = hash_unit(h ^ 0x51) * core::f32::consts::TAU;
                let amount = 0.1 + 0.3 * hash_unit(h ^ 0x52);
                lean += w * Vec3::new(angle.cos(), 0.3 * angle.sin(), angle.sin()) * amount;
                height += w * (0.7 + 0.55 * hash_unit(h ^ 0x53));
                dryness += w * hash_unit(h ^ 0x54);
                total += w;
                x += 1;
            }
            y += 1;
        }
        z += 1;
    }
    Clump {
        lean: lean / total,
        height: height / total,
        dryness: dryness / total,
    }
}

/// The jittered feature point of cell `cell + (x, y, z)` whose hash is `h`.
fn feature(cell: Vec3, x: i32, y: i32, z: i32, h: u32) -> Vec3 {
    let jitter = Vec3::new(
        hash_unit(h ^ 0x11),
        hash_unit(h ^ 0x12),
        hash_unit(h ^ 0x13),
    );
    cell + Vec3::new(x as f32, y as f32, z as f32) + 0.15 + 0.7 * jitter
}

/// The blade as the natural look draws it: its clump's height factor times a
/// per-blade jitter, the tip leaning with the clump (across `up` only, the length of
/// v0→v2 kept), and the width times `width_scale` (the fades).
pub fn dressed_blade(blade: &Blade, clump: &Clump, jitter: f32, width_scale: f32) -> Blade {
    let v0 = blade.root();
    let up = blade.up_dir();
    let scale = clump.height * (0.9 + 0.2 * jitter);
    let sideways = clump.lean - up * clump.lean.dot(up);
    let lean = |p: Vec3| {
        let d = p - v0;
        let len = d.length();
        v0 + (d + sideways * len).normalize_or_zero() * len * scale
    };
    let mut out = blade.with_curve(lean(blade.guide()), lean(blade.tip()));
    out.v1.w = blade.height() * scale;
    out.v2.w = blade.width() * width_scale;
    out
}

/// A visible blade as the natural look draws it, written by the compute pass for the
/// draw (80 bytes): the dressed blade and its tint, coverage and density
/// ([`dress`]).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DressedBlade {
    /// The blade as drawn.
    pub blade: Blade,
    /// Tint (rgb); coverage mask and local density ([`pack_coverage`]) in w.
    pub tint: Vec4,
}

/// What the natural look draws of blade `id` seen from `camera`: the blade dressed by
/// its `clump` (`clump_at` of its root, made once per field by the clump pass), a per-blade jitter and the fades of the enabled culling tests (width to
/// zero before the test removes it), widened to a pixel where it is thinner; its tint
/// (rgb) and, in w, whether it is drawn (a blade thinner than a pixel is drawn a
/// pixel wide with the probability of its coverage, by a per-blade hash: the same
/// every frame, so no shimmer) and the field's local density for the occlusion
/// ([`pack_coverage`]).
pub fn dress(
    blade: &Blade,
    clump: &Clump,
    id: u32,
    camera: Vec3,
    cull: &crate::cull::CullParams,
    look: &LookParams,
) -> (Blade, Vec4) {
    use crate::cull::{DISTANCE, ORIENTATION, orientation_alignment, projected_distance};
    let h1 = hash_unit(id ^ hash_u32(look.seed));
    let h2 = hash_unit(hash_u32(id) ^ 0x9e37_79b9);
    let dproj = projected_distance(blade, camera);
    let mut fade = 1.0;
    let mut density = 1.0;
    if cull.enabled & DISTANCE != 0 {
        fade = distance_fade(dproj, cull.max_distance, cull.buckets, id);
        density = kept_share(dproj, cull.max_distance, cull.buckets);
    }
    if cull.enabled & ORIENTATION != 0 {
        let alignment = orientation_alignment(blade, camera);
        fade *= orientation_fade(alignment, cull.orientation_threshold);
    }
    let distance = (blade.midpoint() - camera).length();
    let (width, alpha) = thin_coverage(blade.width() * fade, look.pixel_angle * distance);
    let scale = if blade.width() > 0.0 {
        width / blade.width()
    } else {
        0.0
    };
    let dressed = dressed_blade(blade, clump, h1, scale);
    let h3 = hash_unit(hash_u32(id ^ 0x2545_f491));
    // Whole blades, one "sample": a fragment stage writing a per-sample mask made
    // the H100's grass draw 3.8 ms slower at 4x MSAA (1,048,576 blades, edge camera),
    // so a thin blade is drawn a pixel wide with probability alpha, or not at all.
    let mask = coverage_mask(alpha, 1, h3);
    let tint = blade_tint(clump, h1, h2).extend(pack_coverage(mask, density));
    (dressed, tint)
}

/// One varying for a blade's coverage mask (0..255) and the local density (0..1):
/// mask + density/2, exact for both (the mask is the whole part).
pub fn pack_coverage(mask: u32, density: f32) -> f32 {
    mask as f32 + 0.5 * density.clamp(0.0, 1.0)
}

/// The (mask, density) of [`pack_coverage`].
pub fn unpack_coverage(packed: f32) -> (u32, f32) {
    let mask = packed.floor();
    (mask as u32, 2.0 * (packed - mask))
}

/// The samples a blade of coverage `alpha` covers in a pixel of `samples` samples:
/// floor(alpha·samples + h) of them (`h` in 0..1 a per-blade hash, so on average
/// alpha·samples, and the same every frame: no shimmer), starting at a sample picked
/// by the hash so thin neighbours do not all take the first. With one sample a thin
/// blade is drawn whole with probability alpha.
pub fn coverage_mask(alpha: f32, samples: u32, h: f32) -> u32 {
    let samples = samples.clamp(1, 8);
    let full = (1u32 << samples) - 1;
    let count = ((alpha.clamp(0.0, 1.0) * samples as f32 + h) as u32).min(samples);
    if count >= samples {
        return full;
    }
    let bits = (1u32 << count) - 1;
    let shift = (h * 7919.0) as u32 % samples;
    ((bits << shift) | (bits >> (samples - shift))) & full
}

// ---- colour --------------------------------------------------------------------

/// Fresh blade colour (linear albedo).
pub const FRESH: Vec3 = Vec3::new(0.045, 0.16, 0.018);
/// Half-dry blade colour.
pub const RIPE: Vec3 = Vec3::new(0.11, 0.19, 0.03);
/// Dry blade colour.
pub const DRY: Vec3 = Vec3::new(0.30, 0.25, 0.09);

/// The palette from fresh (0) through ripe to dry (1).
pub fn palette(dryness: f32) -> Vec3 {
    let t = dryness.clamp(0.0, 1.0);
    if t < 0.5 {
        FRESH.lerp(RIPE, 2.0 * t)
    } else {
        RIPE.lerp(DRY, 2.0 * t - 1.0)
    }
}

/// A blade's own colour: its clump's place in the palette moved by a per-blade
/// jitter (`hash` 0..1), the value ±15 % by a second hash.
pub fn blade_tint(clump: &Clump, hash: f32, hash2: f32) -> Vec3 {
    let dryness = clump.dryness * 0.8 + 0.25 * (hash - 0.5);
    palette(dryness) * (0.85 + 0.3 * hash2)
}

/// Albedo at height `v` (0 root, 1 tip): the tint, darker at the root and drier
/// towards the tip.
pub fn blade_albedo(tint: Vec3, v: f32) -> Vec3 {
    let v = v.clamp(0.0, 1.0);
    let drier = tint.lerp(DRY, 0.45 * v * v * v);
    drier * (0.55 + 0.45 * v)
}

// ---- leaf shading --------------------------------------------------------------

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
    use crate::shade::value_noise;
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
    use crate::shade::{MATERIAL_SOIL, surface_albedo, value_noise};
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

/// 0 below `a`, 1 above `b`, the cubic 3t² − 2t³ between.
pub fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

// ---- fades ---------------------------------------------------------------------

/// Width kept by the distance test's fade: blade `id`'s bucket b = id mod n is
/// removed once n·(1 − dproj/dmax) < b; over the last unit before that the blade
/// narrows to nothing, clamp(n·(1 − dproj/dmax) − b, 0, 1), so it leaves without a pop.
pub fn distance_fade(dproj: f32, max_distance: f32, buckets: u32, id: u32) -> f32 {
    let position = crate::cull::distance_bucket_position(dproj, max_distance, buckets);
    let bucket = (id % buckets.max(1)) as f32;
    (position - bucket).clamp(0.0, 1.0)
}

/// Width of the band before the orientation threshold over which a blade narrows.
pub const ORIENTATION_BAND: f32 = 0.08;

/// Width kept by the orientation test's fade: 1 below threshold − band, 0 at the
/// threshold where the test removes the blade.
pub fn orientation_fade(alignment: f32, threshold: f32) -> f32 {
    ((threshold - alignment) / ORIENTATION_BAND).clamp(0.0, 1.0)
}

/// Relative density of the field at `dproj`: the share of the distance test's
/// buckets kept there (1 with the test off).
pub fn kept_share(dproj: f32, max_distance: f32, buckets: u32) -> f32 {
    let position = crate::cull::distance_bucket_position(dproj, max_distance, buckets);
    ((position + 1.0) / buckets.max(1) as f32).clamp(0.0, 1.0)
}

/// Coverage of a blade narrower than `min_width` (a pixel at its distance): the drawn
/// width is clamped to `min_width` and the fragment's alpha (alpha to coverage
/// under MSAA) is the share of it the blade really covers.
pub fn thin_coverage(width: f32, min_width: f32) -> (f32, f32) {
    if width >= min_width || min_width <= 0.0 {
        (width, 1.0)
    } else {
        (min_width, (width / min_width).max(0.0))
    }
}

// ---- sky, fog, tone map -----------------------------------------------------------

/// Angular radius of the sun disc, radians (about 1.5× the real sun, so it reads).
pub const SUN_RADIUS: f32 = 0.012;

/// cos of [`SUN_RADIUS`] and of 1.2 times it, as constants (1 − x²/2, exact to f32
/// at these angles): a per-pixel cos costs a software device dearly.
const SUN_COS: (f32, f32) = (
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

// ---- shadows -------------------------------------------------------------------

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cull::{cull_distance, cull_orientation, orientation_alignment};

    #[test]
    fn clumps_are_seeded_continuous_and_varied() {
        let p = Vec3::new(3.3, 0.0, -7.1);
        assert_eq!(clump_at(p, 1.6, 5), clump_at(p, 1.6, 5));
        assert_ne!(clump_at(p, 1.6, 5), clump_at(p, 1.6, 6));
        // Along a line 40 units long in steps of 1/400 of a clump, no value jumps:
        // the blend is continuous (a hard Voronoi border would jump by up to 0.55).
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        let mut last = clump_at(Vec3::ZERO, 1.6, 5);
        let step = 1.6 / 400.0;
        for i in 1..(40.0 / step) as i32 {
            let c = clump_at(
                Vec3::new(i as f32 * step, 0.0, 0.3 * i as f32 * step),
                1.6,
                5,
            );
            assert!((c.height - last.height).abs() < 0.02, "height jumps at {i}");
            assert!(
                (c.dryness - last.dryness).abs() < 0.03,
                "dryness jumps at {i}"
            );
            assert!((c.lean - last.lean).length() < 0.02, "lean jumps at {i}");
            (lo, hi) = (lo.min(c.height), hi.max(c.height));
            last = c;
        }
        // Yet clumps differ: the height factor spans much of its range.
        assert!(hi - lo > 0.3, "{lo}..{hi}");
    }

    #[test]
    fn a_clump_packs_into_one_vec4() {
        let c = clump_at(Vec3::new(1.0, 0.0, 2.0), 1.6, 3);
        let back = Clump::unpack(c.pack());
        assert_eq!((back.lean.x, back.lean.z), (c.lean.x, c.lean.z));
        assert_eq!(
            (back.height, back.dryness, back.lean.y),
            (c.height, c.dryness, 0.0)
        );
    }

    #[test]
    fn a_dressed_blade_keeps_its_root_and_leans_sideways() {
        let b = Blade::at_rest(Vec3::new(1.0, 0.0, 2.0), Vec3::Y, 0.3, 2.0, 0.1, 9.0);
        let clump = Clump {
            lean: Vec3::new(0.3, 5.0, 0.0),
            height: 0.8,
            dryness: 0.5,
        };
        let d = dressed_blade(&b, &clump, 0.5, 0.5);
        assert_eq!(d.root(), b.root());
        // The up part of the lean is dropped; the tip moves towards +X; the length
        // v0→v2 is the height times the factor (0.8 · 1.0).
        assert!(d.tip().x > b.tip().x && (d.tip().z - b.tip().z).abs() < 1e-6);
        assert!(((d.tip() - d.root()).length() - 1.6).abs() < 1e-5);
        assert!((d.height() - 1.6).abs() < 1e-5);
        assert!((d.width() - 0.05).abs() < 1e-7);
        assert_eq!(d.stiffness(), b.stiffness());
    }

    #[test]
    fn rounded_normals_are_unit_and_tilt_towards_each_edge() {
        let (n, t1) = (Vec3::Z, Vec3::X);
        assert!((rounded_normal(n, t1, 0.5) - n).length() < 1e-6);
        for u in [0.0, 0.2, 0.7, 1.0] {
            let r = rounded_normal(n, t1, u);
            assert!((r.length() - 1.0).abs() < 1e-5);
            assert_eq!(r.x > 0.0, u > 0.5, "u = {u}: {r}");
        }
        assert!((rounded_normal(n, t1, 1.0).x - ROUNDING.sin()).abs() < 1e-5);
    }

    #[test]
    fn translucency_only_with_the_sun_behind() {
        let facing = Vec3::Z;
        let eye = Vec3::Z;
        // The sun on the viewer's side: nothing comes through.
        for l in [
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(0.0, 0.99, 0.14),
        ] {
            assert_eq!(translucency(facing, l.normalize(), eye), 0.0);
        }
        // Behind the blade: light through it, most when looking into the sun.
        let side = translucency(facing, Vec3::new(0.8, 0.0, -0.6), eye);
        let into = translucency(facing, -Vec3::Z, eye);
        assert!(side > 0.0 && into > side, "{side} {into}");
        assert_eq!(soft_specular(facing, -Vec3::Z, eye), 0.0);
        assert!(soft_specular(facing, Vec3::Z, eye) > 0.09);
    }

    #[test]
    fn occlusion_grows_towards_the_root_and_with_density() {
        assert_eq!(ambient_occlusion(1.0, 1.0), 1.0);
        assert!((ambient_occlusion(0.0, 1.0) - 0.25).abs() < 1e-6);
        let mut last = 0.0;
        for i in 0..=10 {
            let ao = ambient_occlusion(i as f32 / 10.0, 1.0);
            assert!(ao > last);
            last = ao;
        }
        assert!(ambient_occlusion(0.2, 0.3) > ambient_occlusion(0.2, 1.0));
        assert_eq!(ambient_occlusion(0.0, 0.0), 1.0);
    }

    #[test]
    fn tone_map_is_monotonic_from_zero() {
        assert_eq!(aces(0.0), 0.0);
        assert_eq!(tone_map(Vec3::ZERO, 3.0), Vec3::ZERO);
        let mut last = 0.0;
        for i in 1..2000 {
            let y = aces(i as f32 * 0.01);
            assert!(y >= last && y <= 1.0);
            last = y;
        }
        assert!(last > 0.99);
        // Mid grey stays mid: 0.18 maps near 0.27 (display linear).
        assert!((aces(0.18) - 0.267).abs() < 0.01, "{}", aces(0.18));
        assert!(tone_map(Vec3::splat(0.1), 2.0).x > tone_map(Vec3::splat(0.1), 1.0).x);
    }

    #[test]
    fn fades_reach_zero_where_the_tests_remove_the_blade() {
        // Distance: walk the blade outwards; the width falls to 0 no later than the
        // test removes it, and is 1 well inside.
        let (dmax, n) = (40.0, 8);
        for id in 0..16 {
            let mut removed_at = None;
            for step in 0..4100 {
                let d = step as f32 * 0.01;
                let b = Blade::at_rest(Vec3::new(d, 0.0, 0.0), Vec3::Y, 0.0, 2.0, 0.1, 9.0);
                if cull_distance(&b, id, Vec3::ZERO, dmax, n) {
                    removed_at.get_or_insert(d);
                } else {
                    let fade = distance_fade(d, dmax, n, id);
                    // 0.01 units before the cut, the blade is thinner than 1/50.
                    assert!((0.0..=1.0).contains(&fade));
                    if cull_distance(
                        &Blade::at_rest(Vec3::new(d + 0.01, 0.0, 0.0), Vec3::Y, 0.0, 2.0, 0.1, 9.0),
                        id,
                        Vec3::ZERO,
                        dmax,
                        n,
                    ) {
                        assert!(fade < 0.02, "id {id} at {d}: {fade}");
                    }
                }
            }
            assert!(removed_at.is_some());
        }
        assert_eq!(distance_fade(0.0, dmax, n, 7), 1.0);
        // Orientation: 0 at the threshold, 1 a band below.
        assert_eq!(orientation_fade(0.9, 0.9), 0.0);
        assert!(orientation_fade(0.9 - ORIENTATION_BAND, 0.9) > 0.9999);
        assert_eq!(orientation_fade(0.5, 0.9), 1.0);
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 9.0);
        let camera = Vec3::new(-10.0, 2.0, 0.5);
        let a = orientation_alignment(&b, camera);
        assert!(cull_orientation(&b, camera, 0.9) && orientation_fade(a, 0.9) == 0.0);
        assert_eq!(kept_share(0.0, dmax, n), 1.0);
        assert!(kept_share(35.0, dmax, n) < 0.3);
    }

    #[test]
    fn coverage_masks_hold_alpha_on_average() {
        for samples in [1u32, 2, 4, 8] {
            assert_eq!(coverage_mask(1.0, samples, 0.3), (1 << samples) - 1);
            assert_eq!(coverage_mask(0.0, samples, 0.0), 0);
            for alpha in [0.1f32, 0.35, 0.5, 0.8] {
                let n = 1000;
                let bits: u32 = (0..n)
                    .map(|i| coverage_mask(alpha, samples, (i as f32 + 0.5) / n as f32))
                    .map(|m| {
                        assert!(m < (1 << samples));
                        m.count_ones()
                    })
                    .sum();
                let mean = bits as f32 / (n * samples) as f32;
                assert!((mean - alpha).abs() < 0.01, "{samples}x at {alpha}: {mean}");
            }
        }
    }

    #[test]
    fn coverage_and_density_share_a_varying() {
        for mask in [0u32, 1, 5, 255] {
            for density in [0.0f32, 0.125, 0.5, 0.99] {
                let (m, d) = unpack_coverage(pack_coverage(mask, density));
                assert_eq!(m, mask);
                assert!((d - density).abs() < 1e-4, "{mask} {density}: {d}");
            }
        }
    }

    #[test]
    fn thin_blades_keep_their_coverage() {
        assert_eq!(thin_coverage(0.2, 0.1), (0.2, 1.0));
        let (w, alpha) = thin_coverage(0.025, 0.1);
        assert_eq!(w, 0.1);
        assert!((w * alpha - 0.025).abs() < 1e-7);
    }

    #[test]
    fn the_sky_has_a_sun_and_fog_tends_to_it() {
        let sun = Vec3::new(0.3, 0.5, 0.8).normalize();
        let at_sun = sky(sun, sun);
        let away = sky(Vec3::new(-0.3, 0.5, -0.8).normalize(), sun);
        assert!(at_sun.x > 10.0 * away.x, "{at_sun} {away}");
        assert!((SUN_COS.0 - SUN_RADIUS.cos()).abs() < 1e-7);
        assert!((SUN_COS.1 - (1.2 * SUN_RADIUS).cos()).abs() < 1e-7);
        // Deeper blue overhead than at the horizon; darker below it.
        let zenith = sky(Vec3::Y, sun);
        let horizon = sky(Vec3::X, sun);
        assert!(zenith.z / zenith.x > horizon.z / horizon.x);
        assert!(sky(-Vec3::Y, sun).length() < horizon.length());
        let green = Vec3::new(0.1, 0.3, 0.05);
        assert_eq!(fog(green, 0.0, Vec3::X, sun, 0.01), green);
        let far = fog(green, 1e5, Vec3::X, sun, 0.01);
        assert!((far - fog_colour(Vec3::X, sun)).length() < 1e-4);
    }

    #[test]
    fn the_sun_sees_the_scene_and_the_map_finds_shadows() {
        let to_sun = Vec3::new(0.4, 0.8, 0.3).normalize();
        let m = sun_view_proj(to_sun, Vec3::ZERO, 10.0);
        let c = shadow_coord(m, Vec3::ZERO);
        assert!((c - Vec3::new(0.5, 0.5, 0.5)).length() < 1e-5, "{c}");
        // Towards the sun is nearer to it (smaller depth); across stays in the map.
        assert!(shadow_coord(m, to_sun * 5.0).z < c.z);
        let across = shadow_coord(m, to_sun.cross(Vec3::Y).normalize() * 9.0);
        assert!(across.x > 0.0 && across.x < 1.0 && across.y > 0.0 && across.y < 1.0);
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 9.0);
        assert!(in_shadow_map(m, &b));
        let far = Blade::at_rest(Vec3::new(30.0, 0.0, 0.0), Vec3::Y, 0.0, 2.0, 0.1, 9.0);
        assert!(!in_shadow_map(m, &far));
        assert!(casts_shadow(m, &b, Vec3::new(3.0, 2.0, 0.0), 5.0));
        assert!(!casts_shadow(m, &b, Vec3::new(6.0, 2.0, 0.0), 5.0));
        // A map holding depth 0.4 everywhere shadows a point at depth 0.5 and lights
        // one at 0.3; outside the map is lit.
        let map = |_: i32, _: i32| 0.4;
        assert_eq!(shadow_factor(Vec3::new(0.5, 0.5, 0.5), 64, 0.001, map), 0.0);
        assert_eq!(shadow_factor(Vec3::new(0.5, 0.5, 0.3), 64, 0.001, map), 1.0);
        assert_eq!(shadow_factor(Vec3::new(1.5, 0.5, 0.5), 64, 0.001, map), 1.0);
        // Half the map occluded: a point on the edge is half lit.
        let half = |x: i32, _: i32| if x < 32 { 0.4 } else { 1.0 };
        let edge = shadow_factor(Vec3::new(0.5, 0.5, 0.5), 64, 0.001, half);
        assert!((edge - 0.5).abs() < 1e-5, "{edge}");
    }

    #[test]
    fn palette_runs_fresh_to_dry_and_tips_are_drier() {
        assert_eq!(palette(0.0), FRESH);
        assert_eq!(palette(1.0), DRY);
        assert_eq!(palette(0.5), RIPE);
        let tint = palette(0.1);
        let (root, tip) = (blade_albedo(tint, 0.0), blade_albedo(tint, 1.0));
        assert!(root.length() < tip.length());
        // Redder (drier) relative to green at the tip.
        assert!(tip.x / tip.y > root.x / root.y);
    }
}
