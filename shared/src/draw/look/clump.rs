//! Clumps and colour: blades grow in Voronoi clumps that share lean, height and
//! dryness (Wohllaib, *Procedural Grass in Ghost of Tsushima*, GDC 2021), each blade
//! dressed from its clump and tinted from a palette of fresh, ripe and dry grass.

use crate::Blade;
use crate::draw::look::LookParams;
use crate::draw::look::coverage::{
    coverage_mask, distance_fade, kept_share, orientation_fade, pack_coverage, thin_coverage,
};
use crate::noise::{hash_u32, hash_unit};
use spirv_std::glam::{Vec3, Vec4};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

fn hash_cell(x: i32, y: i32, z: i32, seed: u32) -> u32 {
    hash_u32(
        (x as u32).wrapping_mul(0x8da6_b343)
            ^ (y as u32).wrapping_mul(0xd816_3841)
            ^ (z as u32).wrapping_mul(0xcb1a_b31f)
            ^ hash_u32(seed),
    )
}

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
    /// Tint (rgb); coverage mask, species and local density ([`pack_coverage`]) in w.
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
    cull: &crate::cull::blade::CullParams,
    look: &LookParams,
) -> (Blade, Vec4) {
    use crate::cull::blade::{
        DISTANCE, ORIENTATION, orientation_alignment, projected_distance, under_edge_on_guard,
    };
    let h1 = blade_jitter(id, look.seed);
    let h2 = hash_unit(hash_u32(id) ^ 0x9e37_79b9);
    let dproj = projected_distance(blade, camera);
    let mut fade = 1.0;
    let mut density = 1.0;
    if cull.enabled & DISTANCE != 0 {
        fade = distance_fade(dproj, cull.max_distance, cull.buckets, id);
        density = kept_share(dproj, cull.max_distance, cull.buckets);
    }
    if cull.enabled & ORIENTATION != 0 {
        // Only a blade the test would remove once edge-on (narrower on screen than
        // the test's guard) narrows as it turns.
        let alignment = orientation_alignment(blade, camera);
        if under_edge_on_guard(blade, camera, alignment, cull) {
            fade *= orientation_fade(alignment, cull.orientation_threshold);
        }
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
    let species = crate::species::of(blade);
    let tint = blade_tint(clump, h1, h2).extend(pack_coverage(mask, density, species));
    (dressed, tint)
}

/// The per-blade jitter of blade `id` in a field of `seed` (0..1): its height within
/// its clump's and its tint.
pub fn blade_jitter(id: u32, seed: u32) -> f32 {
    hash_unit(id ^ hash_u32(seed))
}

/// Blade `id` as it casts its shadow: dressed by its `clump` and jitter as the
/// natural look draws it ([`dress`]), without the fades and the coverage that the
/// camera's distance and direction give it, so its shadow is the same wherever the
/// camera looks.
pub fn caster_blade(blade: &Blade, clump: &Clump, id: u32, seed: u32) -> Blade {
    dressed_blade(blade, clump, blade_jitter(id, seed), 1.0)
}

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

/// [`blade_albedo`] for a blade of `species`: its head in the species' colour
/// (`species::albedo`), as bright against the ripe grass as its tint is.
pub fn species_albedo(tint: Vec3, v: f32, species: u32) -> Vec3 {
    let value = (tint.length() / RIPE.length()).clamp(0.7, 1.3);
    crate::species::albedo(species, blade_albedo(tint, v), v, value)
}
