//! The counter buffer's words: what the culling tests removed, the blades drawn by
//! each path, the mesh path's buckets, the rasterizer's pixels and the far tiles.

use crate::cull::blade as cull;
use crate::draw::meshlet::{BUCKETS, BinLayout, MESH_DRAWS, SPILL_DRAW};

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
// Word 5 is free: each blade the pass looks at adds to one of the outcomes' counters
// (visible, removed by a test, or far), whose sum is the blades examined
// ([`examined`]).
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
/// Pixels the compute rasterizer's far blades covered on the target (their coverage
/// drew them), counted by the rasterizer (`raster::raster_blade`'s plots).
pub const COUNTER_RASTER_COVERED: usize = 7;
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
/// Blades the compute pass handed to its collision pass (`layout::SPEC_COLLIDERS`):
/// those whose slot of the colliders' grid holds a collider, listed at
/// `layout::BINDING_NEAR` and simulated and tested there.
pub const COUNTER_NEAR: usize = COUNTER_NEAR_CASTERS + 1;
/// Blades a cutter cut this frame (`sim::cut`), one device atomic each.
pub const COUNTER_CUTS: usize = COUNTER_NEAR + 1;
/// Of those, the cuts the cut table had no room for (`sim::cut::place`): dropped.
pub const COUNTER_CUTS_DROPPED: usize = COUNTER_CUTS + 1;
/// First of the mesh path's counts of visible blades by bucket (strip length, and
/// for the longest strips the band of distance: `meshlet::bucket_of`,
/// [`strip_counter`]), counted by the compute pass as it bins them. They begin a
/// 128-byte line of their own (word 32), away from the counters every workgroup adds
/// to (the NVIDIA H100's pass took 0.003 ms longer at 4 M blades with them in the
/// same line; with each bucket's count in a line of its own, 0.003 ms longer too).
pub const COUNTER_STRIPS: usize = 32;
/// The mesh path's blades that found no room in their bucket's part of the binned
/// list (`meshlet::BinLayout`): they go to the list's spill part, drawn at the most
/// segments (`meshlet::SPILL_DRAW`).
pub const COUNTER_SPILLED: usize = COUNTER_STRIPS + BUCKETS as usize;
/// Number of `u32` counters (words 5 and 18 to 31 unused). The compute pass tallies each
/// in workgroup memory and adds it with one device atomic, a thread a counter.
pub const COUNTER_COUNT: usize = COUNTER_SPILLED + 1;

/// Bytes of the counters at the counter buffer's start: what the frame resets and
/// reads back.
pub const COUNTER_BYTES: u64 = (COUNTER_COUNT * 4) as u64;

/// Words of the counter buffer past the counters, which the frame's reset leaves:
/// the binned list's layout ([`BIN_LAYOUT`]) and the mesh draws' slices
/// ([`DRAW_SLICES`]).
pub const COUNTER_WORDS: usize = DRAW_SLICES + 2 * MESH_DRAWS as usize;
/// First of the binned list's layout, `BUCKETS + 1` words kept from frame to frame:
/// bucket b's part of the list starts at word b and ends at word b + 1
/// (`meshlet::BinLayout`). The compute pass bins into it; the draw pass reads it for
/// its draws and writes the next frame's from this frame's counts.
pub const BIN_LAYOUT: usize = 64;
/// First of the mesh draws' slices of the binned list, two words per draw (first
/// slot, strips), written by the draw pass for the mesh stage ([`draw_slice`]).
pub const DRAW_SLICES: usize = BIN_LAYOUT + BUCKETS as usize + 1;

/// The blades the compute pass looked at: each adds to exactly one outcome's count
/// (visible, removed by one of the four tests, or far).
pub fn examined(counters: &[u32]) -> u32 {
    counters[COUNTER_VISIBLE]
        + counters[COUNTER_ORIENTATION]
        + counters[COUNTER_FRUSTUM]
        + counters[COUNTER_DISTANCE]
        + counters[COUNTER_OCCLUSION]
        + counters[COUNTER_FAR]
}

/// Bucket `bucket`'s part of the binned list in a list of `blades` slots, from
/// the layout words ([`BIN_LAYOUT`]): (first slot, room), clamped to the list's
/// first half (a layout the frame before made for more blades).
pub fn bin_part(counters: &[u32], bucket: u32, blades: u32) -> (u32, u32) {
    let at = BIN_LAYOUT + bucket as usize;
    let start = counters[at].min(blades);
    let end = counters[at + 1].min(blades);
    (start, end.max(start) - start)
}

/// The draw pass's part in the binning, after the compute pass has binned a list of
/// `blades` slots: each mesh draw's slice ([`DRAW_SLICES`]: a bucket's blades that
/// found room in its part, then those that spilled), and the next frame's layout
/// from this frame's counts ([`BinLayout::room`] each, in bucket order, clamped to
/// the list's first half).
pub fn lay_out_draws(counters: &mut [u32], blades: u32) {
    let mut total = 0;
    let mut bucket = 0;
    while bucket < BUCKETS {
        total += counters[strip_counter(bucket)];
        bucket += 1;
    }
    let mut next = 0;
    bucket = 0;
    while bucket < BUCKETS {
        let count = counters[strip_counter(bucket)];
        // This frame's part, read before the next frame's start overwrites it.
        let (start, room) = bin_part(counters, bucket, blades);
        let at = DRAW_SLICES + 2 * bucket as usize;
        counters[at] = start;
        counters[at + 1] = count.min(room);
        counters[BIN_LAYOUT + bucket as usize] = next;
        next = (next + BinLayout::room(count, total, blades)).min(blades);
        bucket += 1;
    }
    counters[BIN_LAYOUT + BUCKETS as usize] = next;
    let at = DRAW_SLICES + 2 * SPILL_DRAW as usize;
    counters[at] = blades;
    counters[at + 1] = counters[COUNTER_SPILLED].min(blades);
}

/// Mesh draw `draw`'s slice of the binned list: (first slot, strips).
pub fn draw_slice(counters: &[u32], draw: u32) -> (u32, u32) {
    let at = DRAW_SLICES + 2 * draw as usize;
    (counters[at], counters[at + 1])
}

/// The counter of `bucket`'s blades (`counters[strip_counter(b)]`).
pub fn strip_counter(bucket: u32) -> usize {
    COUNTER_STRIPS + bucket as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cull::lod::MAX_LEVEL;
    use crate::draw::meshlet::*;
    use spirv_std::glam::UVec3;

    #[test]
    fn the_counters_fit_one_workgroup() {
        const { assert!(COUNTER_NEAR_CASTERS < COUNTER_STRIPS) };
        const { assert!(COUNTER_COUNT <= BIN_LAYOUT) };
        // The compute pass's workgroups add one counter a thread.
        const { assert!(COUNTER_COUNT <= 64) };
    }

    /// The compute pass's binning, the draw pass's slices and the mesh stage's
    /// reading, run on the host over four frames: the first with no layout (every
    /// blade spills), the second laid out by the first's counts (none spills), the
    /// third with the blades' levels changed (some spill), the fourth laid out by the
    /// third's. Every blade is drawn once with its strip, each vertex of each strip
    /// once. Blades of every length in every band (the band of blade i is i mod
    /// [`NEAR_BANDS`]), workgroups of 128 adding to the counters in turn.
    #[test]
    fn binned_blades_are_drawn_once_each_with_their_strip() {
        let blades = 1000;
        let top = top_segments(MAX_LEVEL);
        let mut counters = [0u32; COUNTER_WORDS];
        let mut spilled_in = Vec::new();
        for frame in 0..4u32 {
            let shift = if frame >= 2 { 331 } else { 0 };
            let levels: Vec<f32> = (0..blades)
                .map(|i| {
                    let k = (i * 7919 + shift) % blades;
                    1.0 + k as f32 / blades as f32 * (MAX_LEVEL - 1.0)
                })
                .collect();
            let band = |i: usize| i as u32 % NEAR_BANDS;
            let bucket = |i: usize| bucket_of(strip_segments(levels[i]), band(i), top);
            counters[..COUNTER_COUNT].fill(0);
            let mut binned = vec![StripBlade::default(); 2 * blades as usize];
            let mut written = vec![false; binned.len()];
            for group in levels.chunks(128).enumerate() {
                let (g, group) = group;
                let mut tally = [0u32; BUCKETS as usize];
                let mut place = Vec::new();
                for i in 0..group.len() {
                    let b = bucket(g * 128 + i) as usize;
                    place.push(tally[b]);
                    tally[b] += 1;
                }
                let mut places = [BinPlaces::default(); BUCKETS as usize];
                for (b, &count) in tally.iter().enumerate() {
                    let first = counters[strip_counter(b as u32)];
                    counters[strip_counter(b as u32)] += count;
                    let (start, room) = bin_part(&counters, b as u32, blades);
                    let fit = BinPlaces::fitting(count, first, room);
                    let spilled = counters[COUNTER_SPILLED];
                    counters[COUNTER_SPILLED] += count - fit;
                    places[b] = BinPlaces::new(fit, (start, first), (blades, spilled));
                }
                for (i, &level) in group.iter().enumerate() {
                    let source = g * 128 + i;
                    let slot = places[bucket(source) as usize].slot(place[i]) as usize;
                    assert!(!written[slot], "slot {slot} written twice");
                    written[slot] = true;
                    binned[slot] = StripBlade {
                        source: source as u32,
                        level,
                    };
                }
            }
            spilled_in.push(counters[COUNTER_SPILLED]);
            lay_out_draws(&mut counters, blades);
            let mut seen = vec![0u32; blades as usize];
            for draw in 0..MESH_DRAWS {
                let n = draw_segments(draw, top);
                let (base, count) = draw_slice(&counters, draw);
                let grid = mesh_grid(count, n);
                for y in 0..grid.y {
                    for x in 0..grid.x {
                        let first = group_index(UVec3::new(x, y, 0), grid) * strips_per_group(n);
                        let strips = group_strips(count, first, strips_per_group(n));
                        for lane in 0..MESH_THREADS {
                            let (strip, k) = strip_lane(lane, n);
                            if strip < strips {
                                let at = (base + first + strip) as usize;
                                assert!(written[at], "draw {draw} reads slot {at}, not written");
                                let b = binned[at];
                                assert!(strip_segments(b.level) <= n);
                                if draw != SPILL_DRAW {
                                    assert_eq!(strip_segments(b.level), n);
                                }
                                if k < strip_vertices(strip_segments(b.level)) {
                                    seen[b.source as usize] += 1;
                                }
                            }
                        }
                    }
                }
            }
            for (i, &l) in levels.iter().enumerate() {
                assert_eq!(seen[i], strip_vertices(strip_segments(l)), "blade {i}");
            }
        }
        assert_eq!(spilled_in[0], blades, "no layout: every blade spills");
        assert_eq!(spilled_in[1], 0, "laid out by the same counts");
        assert!(
            spilled_in[2] > 0 && spilled_in[2] < blades / 2,
            "{spilled_in:?}"
        );
        assert_eq!(spilled_in[3], 0, "laid out by the same counts");
        let order: Vec<u32> = (0..BUCKETS).map(|d| bucket_segments(d, top)).collect();
        assert_eq!(order[..NEAR_BANDS as usize], [9; NEAR_BANDS as usize]);
        assert_eq!(
            order[NEAR_BANDS as usize..],
            [8, 7, 6, 5, 4, 3, 2, 1],
            "longest first"
        );
    }

    /// The next frame's layout gives every bucket at least its count, in bucket
    /// order, and stays within the list's first half, for fields from empty to full.
    #[test]
    fn the_layout_holds_every_count_within_the_list() {
        let blades = 4_194_304;
        for total in [0, 1, 1000, 1_000_000, 4_000_000, blades] {
            let mut counters = [0u32; COUNTER_WORDS];
            for b in 0..BUCKETS {
                // Uneven counts: most in the middle buckets.
                let share = (b + 1) * (BUCKETS - b);
                let all: u32 = (0..BUCKETS).map(|c| (c + 1) * (BUCKETS - c)).sum();
                counters[strip_counter(b)] = (total as u64 * share as u64 / all as u64) as u32;
            }
            lay_out_draws(&mut counters, blades);
            let mut end = 0;
            for b in 0..BUCKETS {
                let (start, room) = bin_part(&counters, b, blades);
                assert_eq!(start, end, "{total}: bucket {b} after the one before");
                assert!(room >= counters[strip_counter(b)], "{total}: bucket {b}");
                end = start + room;
            }
            assert!(end <= blades);
        }
    }
}
