//! Coverage instead of popping: a thin blade covers part of a pixel's samples, and
//! blades fade over the last stretch of the distance and orientation tests.

#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// One varying for a blade's coverage mask (0..255), its species
/// (`crate::species`) and the local density (0..1): 256·species + mask + density/2,
/// exact for all three (the mask and the species are the whole part, below 2¹⁰, so
/// the density keeps 13 bits).
pub fn pack_coverage(mask: u32, density: f32, species: u32) -> f32 {
    (species * 256 + (mask & 255)) as f32 + 0.5 * density.clamp(0.0, 1.0)
}

/// The (mask, density) of [`pack_coverage`].
pub fn unpack_coverage(packed: f32) -> (u32, f32) {
    let whole = packed.floor();
    ((whole as u32) & 255, 2.0 * (packed - whole))
}

/// The species of [`pack_coverage`].
pub fn coverage_species(packed: f32) -> u32 {
    (packed.floor() as u32) >> 8
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

/// Share of a distance bucket over which a blade narrows before the distance test
/// removes it ([`distance_fade`]). Over a whole bucket every distance had one of its
/// kept buckets narrowed, and the natural look's frame differed from the unculled one
/// by 3.1 of 255 against the paper look's 1.5 (lavapipe, 640x360, 2,048 blades from
/// the field's edge, the orientation test's guard at 2 pixels); over a quarter, 1.8.
pub const DISTANCE_BAND: f32 = 0.25;

/// Width kept by the distance test's fade: blade `id`'s bucket b = id mod n is
/// removed once n·(1 − dproj/dmax) < b; over the last [`DISTANCE_BAND`] of a bucket
/// before that the blade narrows to nothing,
/// clamp((n·(1 − dproj/dmax) − b)/band, 0, 1), so it leaves without a pop.
pub fn distance_fade(dproj: f32, max_distance: f32, buckets: u32, id: u32) -> f32 {
    let position = crate::cull::blade::distance_bucket_position(dproj, max_distance, buckets);
    let bucket = (id % buckets.max(1)) as f32;
    ((position - bucket) / DISTANCE_BAND).clamp(0.0, 1.0)
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
    let position = crate::cull::blade::distance_bucket_position(dproj, max_distance, buckets);
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
