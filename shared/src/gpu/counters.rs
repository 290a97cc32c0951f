//! The counter buffer's words: what the culling tests removed, the blades drawn by
//! each path, the mesh path's buckets, the rasterizer's pixels and the far tiles.

use crate::cull::blade as cull;
use crate::draw::meshlet::BUCKETS;

/// Index in the counter buffer of the number of visible (drawn) blades.
pub const COUNTER_VISIBLE: usize = cull::KEPT as usize;
/// Index of the blades removed by the orientation test.
pub const COUNTER_ORIENTATION: usize = cull::BY_ORIENTATION as usize;
/// Index of the blades removed by the frustum test.
pub const COUNTER_FRUSTUM: usize = cull::BY_FRUSTUM as usize;
/// Index of the blades removed by the distance test.
pub const COUNTER_DISTANCE: usize = cull::BY_DISTANCE as usize;
/// Index of the blades removed by the occlusion test.
pub const COUNTER_OCCLUSION: usize = cull::BY_OCCLUSION as usize;
/// Index of the blades the pass looked at (every blade, counted on the GPU).
pub const COUNTER_EXAMINED: usize = 5;
/// Index of the visible blades drawn by the compute rasterizer (`raster`): their
/// indices fill the visible list from its end, slot k at `blades - 1 - k`
/// ([`far_slot`]).
pub const COUNTER_FAR: usize = 6;

/// The visible list's slot (and the dressed buffer's) of far blade `k` in a field of
/// `blades`: far blades fill the list from its end, the hardware path's from its start,
/// so the two never meet (together at most `blades`).
pub fn far_slot(k: u32, blades: u32) -> u32 {
    blades - 1 - k
}
/// First of the mesh path's counts of visible blades by bucket (strip length, and
/// for the longest strips the band of distance: `meshlet::bucket_of`,
/// `meshlet::strip_counter`), counted by the compute pass.
pub const COUNTER_STRIPS: usize = 8;
/// First of the binning pass's fill counters, one per bucket
/// (`meshlet::binned_counter`).
pub const COUNTER_BINNED: usize = COUNTER_STRIPS + BUCKETS as usize;
/// Pixels the compute rasterizer's far blades covered on the target (their coverage
/// drew them), counted by the rasterizer (`raster::raster_blade`'s plots).
pub const COUNTER_RASTER_COVERED: usize = COUNTER_BINNED + BUCKETS as usize;
/// Of those, the pixels the rasterizer wrote with an atomic: in front of the
/// hardware's depth and of the far blade the pixel held when it looked
/// (`raster::in_front`).
pub const COUNTER_RASTER_WRITTEN: usize = COUNTER_RASTER_COVERED + 1;
/// Far tiles in view in a tiled field (`compute::select_far_tiles`).
pub const COUNTER_TILES: usize = COUNTER_RASTER_WRITTEN + 1;
/// Blades those tiles asked for: the far blades generated, up to the field's room for
/// them ([`GrassParams::blades`](crate::gpu::layout::GrassParams::blades) less [`GrassParams::simulated`](crate::gpu::layout::GrassParams::simulated)).
pub const COUNTER_TILE_BLADES: usize = COUNTER_TILES + 1;
/// Far tiles in view that found no room (drawn with fewer blades or none).
pub const COUNTER_TILES_SHORT: usize = COUNTER_TILE_BLADES + 1;
/// Tiles in the view volume the occlusion test found hidden at tile level (their
/// box behind the occluders' depth pyramid): no blade generated.
pub const COUNTER_TILES_HIDDEN: usize = COUNTER_TILES_SHORT + 1;
/// Blades that cast a shadow into the sun's map this frame (natural look, shadows
/// on): their indices fill the caster list (`layout::BINDING_CASTERS`), whatever the
/// camera's tests decided.
pub const COUNTER_CASTERS: usize = COUNTER_TILES_HIDDEN + 1;
/// Of those, the casters inside the near cascade (`look::shadow::near_sphere`): their
/// indices fill the list's second half, from the field's blade count on.
pub const COUNTER_NEAR_CASTERS: usize = COUNTER_CASTERS + 1;
/// Number of `u32` counters.
pub const COUNTER_COUNT: usize = COUNTER_NEAR_CASTERS + 1;

/// The first binned slot of `bucket`: the blades of the buckets before it, whose
/// counts are `counters[COUNTER_STRIPS..]` (`layout::COUNTER_STRIPS`).
pub fn bucket_base(counters: &[u32], bucket: u32) -> u32 {
    let mut base = 0;
    let mut b = 0;
    while b < bucket {
        base += counters[strip_counter(b)];
        b += 1;
    }
    base
}

/// The counter of `bucket`'s blades (`counters[strip_counter(b)]`).
pub fn strip_counter(bucket: u32) -> usize {
    COUNTER_STRIPS + bucket as usize
}

/// The counter the binning pass fills `bucket` with.
pub fn binned_counter(bucket: u32) -> usize {
    COUNTER_BINNED + bucket as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cull::lod::MAX_LEVEL;
    use crate::draw::meshlet::*;
    use spirv_std::glam::UVec3;

    #[test]
    fn the_counters_fit_one_workgroup() {
        const { assert!(COUNTER_BINNED + BUCKETS as usize <= COUNTER_COUNT) };
        // The compute pass's workgroups add one counter a thread.
        const { assert!(COUNTER_COUNT <= 64) };
    }

    /// The compute pass's binning and the mesh stage's reading, run on the host:
    /// every blade lands once in its bucket, and the lanes of the bucket's
    /// workgroups write each vertex of each strip once. Blades of every length in
    /// every band (the band of blade i is i mod [`NEAR_BANDS`]).
    #[test]
    fn binned_blades_are_drawn_once_each_with_their_strip() {
        let levels: Vec<f32> = (0..1000)
            .map(|i| 1.0 + (i * 7919 % 1000) as f32 / 1000.0 * (MAX_LEVEL - 1.0))
            .collect();
        let top = top_segments(MAX_LEVEL);
        let band = |i: usize| i as u32 % NEAR_BANDS;
        let bucket = |i: usize| bucket_of(strip_segments(levels[i]), band(i), top);
        let mut counters = [0u32; COUNTER_COUNT];
        for i in 0..levels.len() {
            counters[strip_counter(bucket(i))] += 1;
        }
        let mut binned = vec![StripBlade::default(); levels.len()];
        let mut written = vec![false; levels.len()];
        for (source, &level) in levels.iter().enumerate() {
            let b = bucket(source);
            let place = counters[binned_counter(b)];
            counters[binned_counter(b)] += 1;
            let slot = (bucket_base(&counters, b) + place) as usize;
            assert!(!written[slot], "slot {slot} written twice");
            written[slot] = true;
            binned[slot] = StripBlade {
                source: source as u32,
                level,
            };
        }
        assert!(written.iter().all(|&w| w));
        let mut seen = vec![0u32; levels.len()];
        let order: Vec<u32> = (0..BUCKETS).map(|d| bucket_segments(d, top)).collect();
        assert_eq!(order[..NEAR_BANDS as usize], [9; NEAR_BANDS as usize]);
        assert_eq!(
            order[NEAR_BANDS as usize..],
            [8, 7, 6, 5, 4, 3, 2, 1],
            "longest first"
        );
        for (draw, n) in order.into_iter().enumerate() {
            let draw = draw as u32;
            let count = counters[strip_counter(draw)];
            assert_eq!(counters[binned_counter(draw)], count);
            let grid = mesh_grid(count, n);
            let base = bucket_base(&counters, draw);
            for y in 0..grid.y {
                for x in 0..grid.x {
                    let first = group_index(UVec3::new(x, y, 0), grid) * strips_per_group(n);
                    let strips = group_strips(count, first, strips_per_group(n));
                    for lane in 0..MESH_THREADS {
                        let (strip, k) = strip_lane(lane, n);
                        if strip < strips {
                            let b = binned[(base + first + strip) as usize];
                            assert_eq!(strip_segments(b.level), n);
                            assert!(k < strip_vertices(n));
                            seen[b.source as usize] += 1;
                        }
                    }
                }
            }
        }
        for (i, &l) in levels.iter().enumerate() {
            assert_eq!(seen[i], strip_vertices(strip_segments(l)), "blade {i}");
        }
    }
}
