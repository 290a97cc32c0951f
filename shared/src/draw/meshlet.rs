//! The mesh-shader path's blade strips and how blades are grouped into mesh
//! workgroups, after AMD's mesh-shader grass (GPUOpen, *Procedural grass
//! rendering*, 2022), with its task stage's work moved into the compute pass.
//!
//! A blade of level L is a strip of N = ⌈L⌉ segments: 2(N + 1) vertices and exactly
//! 2N triangles (the tessellator's fractional-odd quads make 6N − 4). Its rows lie at
//! v = j / L (the last at 1), so the last segment grows from nothing as L passes a
//! whole number: the shape morphs continuously, as fractional-odd spacing does.
//!
//! The compute pass, which knows each visible blade's level, bins the visible blades
//! as it culls them into one list per bucket ([`BUCKETS`] of them): one per strip
//! length N, the longest strips (the nearest blades, at the level's cap) split further
//! into [`NEAR_BANDS`] bands of distance ([`bucket_of`]). The buckets' parts of the
//! binned list are laid out before the frame's counts are known, from the frame
//! before's ([`BinLayout`]), so the pass writes each blade to its slot at once; a
//! blade its part has no room for spills to the list's second half, drawn at the most
//! segments ([`SPILL_DRAW`]), which draws its strip unchanged. One indirect draw per
//! bucket, nearest first, then the spill's, launches mesh workgroups of
//! [`strips_per_group`] strips each: every workgroup knows its strips from its index
//! alone, with no task stage, no packing and no search. On the NVIDIA H100, which
//! runs graphics stages on a few of its SMs, the work of a task stage costs most there (performance notes,
//! attempt 12).

use crate::Blade;
use crate::cull::lod::{MAX_LEVEL, MAX_SEGMENTS, clamp_unchecked};
use spirv_std::glam::{UVec3, Vec3};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Invocations of a mesh workgroup.
pub const MESH_THREADS: u32 = 32;
/// Most vertices a mesh workgroup writes (the mesh stage's `output_vertices`): 32,
/// which the NVIDIA H100 drew fastest of 24, 32, 64 and 128 (performance notes,
/// attempt 11).
pub const MESHLET_VERTICES: u32 = 32;
/// Most triangles a mesh workgroup writes (`output_primitives_ext`): its strips have
/// 2 fewer triangles than vertices each.
pub const MESHLET_TRIANGLES: u32 = MESHLET_VERTICES - 2;
/// Largest mesh grid along x: the smallest `maxMeshWorkGroupCount[0]` Vulkan allows
/// is 65,535; more workgroups go on along y.
pub const MESH_GRID_WIDTH: u32 = 32_768;
/// Most vertices of one strip: [`MAX_SEGMENTS`] segments.
pub const MAX_STRIP_VERTICES: u32 = 2 * (MAX_SEGMENTS + 1);
/// Bands of distance the longest strips are split into, nearest first, so that the
/// blades nearest the camera, which cover the most pixels, are drawn before those
/// they hide and the depth test rejects the hidden ones' fragments early
/// ([`near_band`]).
pub const NEAR_BANDS: u32 = 8;
/// Buckets, one indirect draw each: strips of 1 to [`MAX_SEGMENTS`] segments, those
/// of the most segments in [`NEAR_BANDS`] bands ([`bucket_of`]).
pub const BUCKETS: u32 = MAX_SEGMENTS + NEAR_BANDS - 1;
/// The mesh draw of the blades that spilled out of their bucket's part of the binned
/// list ([`BinLayout`]), after the buckets' draws: strips of the most segments
/// ([`draw_segments`]).
pub const SPILL_DRAW: u32 = BUCKETS;
/// The grass's mesh draws: one per bucket and the spill's.
pub const MESH_DRAWS: u32 = BUCKETS + 1;

/// The band of a blade `distance` from the camera and `height` tall: 0 within
/// [`FIRST_BAND`] heights, each next band √2 times as far, the last beyond
/// ([`NEAR_BANDS`]).
pub fn near_band(distance: f32, height: f32) -> u32 {
    let ratio = distance / height.max(1e-6);
    // Band k ≥ 1 begins at FIRST_BAND·√2^(k − 1): k = ⌊2·log2(ratio / FIRST_BAND)⌋ + 1,
    // one logarithm rather than a loop over the edges.
    let band = (2.0 * (ratio / FIRST_BAND).log2()).floor() + 1.0;
    clamp_unchecked(band, 0.0, (NEAR_BANDS - 1) as f32) as u32
}

/// The nearest band's reach, in blade heights ([`near_band`]).
pub const FIRST_BAND: f32 = 1.5;

/// The bucket of a visible blade at `level` seen from `camera`, at a level cap of
/// `most`: its strip length and its band of distance ([`near_band`], [`bucket_of`]).
pub fn visible_bucket(level: f32, blade: &Blade, camera: Vec3, most: f32) -> u32 {
    let distance = (blade.root() - camera).length();
    let band = near_band(distance, blade.height());
    bucket_of(strip_segments(level), band, top_segments(most))
}

/// Segments of the longest strips at a level cap of `most` (`lod.most`).
pub fn top_segments(most: f32) -> u32 {
    strip_segments(most)
}

/// The bucket (and draw) of a strip of `segments` in `band`, the longest strips being
/// of `top` segments ([`top_segments`]): the longest in their band's bucket (0 to
/// [`NEAR_BANDS`] − 1), then one bucket per shorter length, longest first, then
/// (unused while no level passes its cap) one per longer length.
pub fn bucket_of(segments: u32, band: u32, top: u32) -> u32 {
    if segments == top {
        band.min(NEAR_BANDS - 1)
    } else if segments < top {
        NEAR_BANDS + (top - 1 - segments)
    } else {
        NEAR_BANDS + top - 1 + (segments - top - 1)
    }
}

/// Segments of the strips of `bucket` ([`bucket_of`]'s inverse in length).
pub fn bucket_segments(bucket: u32, top: u32) -> u32 {
    if bucket < NEAR_BANDS {
        top
    } else if bucket < NEAR_BANDS + top - 1 {
        top - 1 - (bucket - NEAR_BANDS)
    } else {
        top + 1 + (bucket - (NEAR_BANDS + top - 1))
    }
}

/// Segments of the strips of mesh draw `draw`: its bucket's ([`bucket_segments`]), or
/// for [`SPILL_DRAW`] the most any strip has: a strip of ⌈L⌉ segments drawn with more
/// is the same strip, its rows past the tip at the tip ([`strip_row`]), the triangles
/// between them empty.
pub fn draw_segments(draw: u32, top: u32) -> u32 {
    if draw == SPILL_DRAW {
        MAX_SEGMENTS
    } else {
        bucket_segments(draw, top)
    }
}

/// The binned list's layout: bucket b's part is slots `start(b) .. start(b + 1)` of
/// the list's first half (`counters::BIN_LAYOUT`), set by the frame before from its
/// counts ([`BinLayout::room`]); the second half holds the blades that spilled.
pub struct BinLayout;

impl BinLayout {
    /// Slots the next frame gives a bucket that held `count` of this frame's `total`
    /// binned blades, in a list of `blades` slots: its count, and of the slots left
    /// over, half shared evenly among the buckets and half by count, so that a
    /// bucket that grows a little, or one empty this frame, finds room. The rooms add
    /// up to at most `blades` but for float rounding, which the caller clamps.
    pub fn room(count: u32, total: u32, blades: u32) -> u32 {
        // Not `saturating_sub`, which rust-gpu does not compile.
        let spare = blades.max(total) - total;
        let even = spare / 2 / BUCKETS;
        let by_count = ((spare / 2) as f32 * (count as f32 / total.max(1) as f32)) as u32;
        count + even + by_count
    }
}

/// Where one workgroup's blades of one bucket go in the binned list, by their
/// `place` among them: the first `fit` to their bucket's part from `base` on, the
/// others to the spill half (`spill` + place, `spill` already less `fit`).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct BinPlaces {
    /// Blades that fit in the bucket's part.
    pub fit: u32,
    /// Slot of the first of them.
    pub base: u32,
    /// Slot of the first spilled blade less `fit` (wrapping).
    pub spill: u32,
}

impl BinPlaces {
    /// Of a workgroup's `count` blades of a bucket whose part has `room` slots, those
    /// that fit after the `first` slots earlier workgroups took.
    pub fn fitting(count: u32, first: u32, room: u32) -> u32 {
        if room > first {
            count.min(room - first)
        } else {
            0
        }
    }

    /// The places of `fit` blades fitting from slot `first` of a part starting at
    /// slot `start`, the rest after the `spilled` blades of the spill half, which
    /// starts at slot `spill_start`.
    pub fn new(fit: u32, (start, first): (u32, u32), (spill_start, spilled): (u32, u32)) -> Self {
        Self {
            fit,
            base: start + first,
            spill: (spill_start + spilled).wrapping_sub(fit),
        }
    }

    /// The slot of the blade at `place` among the workgroup's of this bucket.
    pub fn slot(&self, place: u32) -> u32 {
        if place < self.fit {
            self.base + place
        } else {
            self.spill.wrapping_add(place)
        }
    }
}

/// Segments of a blade strip at `level`: the level rounded up.
pub fn strip_segments(level: f32) -> u32 {
    clamp_unchecked(level, 1.0, MAX_LEVEL).ceil() as u32
}

/// Where row `j` of a strip at `level` lies along the blade: j / L, at most 1.
pub fn strip_row(j: u32, level: f32) -> f32 {
    (j as f32 / clamp_unchecked(level, 1.0, MAX_LEVEL)).min(1.0)
}

/// Vertices of a strip of `segments` (0 for a dropped blade).
pub fn strip_vertices(segments: u32) -> u32 {
    if segments == 0 { 0 } else { 2 * (segments + 1) }
}

/// Triangles of a strip of `segments`.
pub fn strip_triangles(segments: u32) -> u32 {
    2 * segments
}

/// (u, v) of vertex `k` of a strip at `level`: u alternates across the width (0, 1),
/// v is the row's [`strip_row`].
pub fn strip_coord(k: u32, level: f32) -> (f32, f32) {
    ((k & 1) as f32, strip_row(k >> 1, level))
}

/// Triangle `t` of a strip whose first vertex is `base`: two per segment, wound as
/// the tessellator winds its quads (`vertex_order_ccw` over (u, v)), so on both paths
/// the face the rasteriser calls front is the one the normal t0 × t1 points out of
/// (the fragment stage lights the face it sees by its winding).
pub fn strip_triangle(t: u32, base: u32) -> UVec3 {
    let row = base + 2 * (t >> 1);
    if t & 1 == 0 {
        UVec3::new(row, row + 2, row + 1)
    } else {
        UVec3::new(row + 1, row + 2, row + 3)
    }
}

/// Strips of `segments` one mesh workgroup draws: as many as fit in
/// [`MESHLET_VERTICES`] (8 strips of 1 segment, down to 1 of 8 or 9).
pub fn strips_per_group(segments: u32) -> u32 {
    MESHLET_VERTICES / strip_vertices(segments).max(1)
}

/// A visible blade binned by strip length: what the mesh stage reads it from (the
/// blade's index in the paper look, its dressed slot in the natural look) and its
/// level of detail.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct StripBlade {
    /// Index into the blade buffer (paper look) or slot of the dressed buffer
    /// (natural look).
    pub source: u32,
    /// The level of detail L (the strip has ⌈L⌉ segments).
    pub level: f32,
}

/// The mesh grid of a bucket of strips of `segments` holding `count` strips: enough workgroups of
/// [`strips_per_group`], as (x, y, 1) no wider than [`MESH_GRID_WIDTH`], with fewer
/// than y workgroups past the last strip; (0, 0, 1) for an empty bucket.
pub fn mesh_grid(count: u32, segments: u32) -> UVec3 {
    group_grid(count.div_ceil(strips_per_group(segments)))
}

/// `groups` mesh workgroups as a grid (x, y, 1) no wider than [`MESH_GRID_WIDTH`],
/// with fewer than y workgroups past the last; (0, 0, 1) for none.
pub fn group_grid(groups: u32) -> UVec3 {
    let y = groups.div_ceil(MESH_GRID_WIDTH);
    UVec3::new(groups.div_ceil(y.max(1)), y, 1)
}

/// Strips a workgroup whose first strip is `first` draws of a bucket of `count`: at
/// most `per` (the last workgroup takes what is left). Written without
/// `saturating_sub`, which rust-gpu does not compile.
pub fn group_strips(count: u32, first: u32, per: u32) -> u32 {
    if count > first {
        per.min(count - first)
    } else {
        0
    }
}

/// The flat index of mesh workgroup `group` in a launch of `groups` ([`mesh_grid`]'s
/// inverse).
pub fn group_index(group: UVec3, groups: UVec3) -> u32 {
    group.y * groups.x + group.x
}

/// Where invocation `lane` of a mesh workgroup lies in its strips: (strip, vertex of
/// the strip) for strips of `segments`.
pub fn strip_lane(lane: u32, segments: u32) -> (u32, u32) {
    let vertices = strip_vertices(segments).max(1);
    (lane / vertices, lane % vertices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_have_two_triangles_per_segment_and_reach_the_tip() {
        for level in [1.0, 1.5, 2.0, 4.3, 9.0] {
            let n = strip_segments(level);
            assert_eq!(strip_vertices(n), 2 * (n + 1));
            assert_eq!(strip_triangles(n), 2 * n);
            assert_eq!(strip_row(0, level), 0.0);
            assert_eq!(strip_row(n, level), 1.0);
            // Every triangle uses vertices of the strip, none degenerate in index.
            for t in 0..strip_triangles(n) {
                let tri = strip_triangle(t, 0);
                assert!(tri.max_element() < strip_vertices(n), "{level} {t}");
                assert!(tri.x != tri.y && tri.y != tri.z && tri.x != tri.z);
            }
        }
        assert_eq!(strip_segments(4.3), 5);
        assert_eq!(strip_segments(4.0), 4);
    }

    /// Every strip length and band has a bucket within [`BUCKETS`], the longest
    /// strips' bands first and apart, the others one bucket per length, longest first;
    /// each bucket's length is the one that went in. Bands double with the distance
    /// in heights; a packed level comes back whole.
    #[test]
    fn buckets_hold_each_length_and_the_longest_by_band() {
        for top in 1..=MAX_SEGMENTS {
            let mut seen = Vec::new();
            for segments in 1..=MAX_SEGMENTS {
                for band in 0..NEAR_BANDS {
                    let b = bucket_of(segments, band, top);
                    assert!(b < BUCKETS, "{segments} {band} {top}: {b}");
                    assert_eq!(bucket_segments(b, top), segments);
                    if segments == top {
                        assert_eq!(b, band);
                    } else {
                        assert_eq!(b, bucket_of(segments, 0, top));
                    }
                    seen.push(b);
                }
            }
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len() as u32, BUCKETS);
            // Shorter strips after longer ones.
            assert!(bucket_of(top.max(2) - 1, 0, top.max(2)) >= NEAR_BANDS);
        }
        // Edges at 1.5, 2.12, 3, 4.24, 6, 8.49 and 12 heights.
        let h = 2.0;
        let bands: Vec<u32> = [
            0.0, 2.9, 3.1, 5.9, 6.1, 8.4, 8.6, 16.9, 17.1, 23.9, 24.1, 1e6,
        ]
        .iter()
        .map(|&d| near_band(d, h))
        .collect();
        assert_eq!(bands, [0, 0, 1, 2, 3, 3, 4, 5, 6, 6, 7, 7]);
    }

    #[test]
    fn rows_morph_continuously_across_whole_levels() {
        // Just above a whole level n the extra row sits at the tip; just below, the
        // rows are those of n segments: no jump either way.
        for n in 1..9u32 {
            let below = n as f32 - 1e-4;
            let above = n as f32 + 1e-4;
            for j in 0..=n + 1 {
                let a = strip_row(j.min(strip_segments(below)), below);
                let b = strip_row(j.min(strip_segments(above)), above);
                assert!((a - b).abs() < 1e-3, "n {n} row {j}: {a} against {b}");
            }
        }
    }

    #[test]
    fn each_bucket_fills_its_workgroups_within_the_output_limits() {
        assert_eq!(MAX_SEGMENTS, 9);
        let per: Vec<u32> = (1..=MAX_SEGMENTS).map(strips_per_group).collect();
        assert_eq!(per, [8, 5, 4, 3, 2, 2, 2, 1, 1]);
        for n in 1..=MAX_SEGMENTS {
            let p = strips_per_group(n);
            assert!(p * strip_vertices(n) <= MESHLET_VERTICES, "{n}");
            assert!(p * strip_triangles(n) <= MESHLET_TRIANGLES, "{n}");
            assert!(
                p * strip_triangles(n) <= MESH_THREADS,
                "{n}: one triangle a lane"
            );
            // One strip more would not fit.
            assert!((p + 1) * strip_vertices(n) > MESHLET_VERTICES, "{n}");
        }
    }

    #[test]
    fn mesh_grids_cover_every_strip_within_the_limit() {
        const { assert!(MESH_GRID_WIDTH <= 65_535) };
        for count in [0, 1, 7, 8, 9, 4_194_304, 40_000_000] {
            for n in [1, 2, 9] {
                let g = mesh_grid(count, n);
                let per = strips_per_group(n);
                assert!(g.x <= MESH_GRID_WIDTH);
                let groups = count.div_ceil(per);
                assert!(g.x * g.y >= groups, "{count} {n}");
                // Fewer idle workgroups than rows.
                assert!(g.x * g.y - groups < g.y.max(1), "{count} {n}: {g}");
                if count > 0 {
                    let last = group_index(g - UVec3::new(1, 1, 0), g);
                    assert_eq!(last + 1, g.x * g.y);
                    // An idle workgroup draws nothing.
                    assert_eq!(group_strips(count, last * per, per) == 0, last >= groups);
                } else {
                    assert_eq!(g.x * g.y, 0);
                }
            }
        }
    }
}
