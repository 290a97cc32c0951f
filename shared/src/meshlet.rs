//! The mesh-shader path's blade strips and how blades are grouped into mesh
//! workgroups (issue 17), after AMD's mesh-shader grass (GPUOpen, *Procedural grass
//! rendering*, 2022), with its task stage's work moved into the compute pass.
//!
//! A blade of level L is a strip of N = ⌈L⌉ segments: 2(N + 1) vertices and exactly
//! 2N triangles (the tessellator's fractional-odd quads make 6N − 4). Its rows lie at
//! v = j / L (the last at 1), so the last segment grows from nothing as L passes a
//! whole number: the shape morphs continuously, as fractional-odd spacing does.
//!
//! The compute pass, which knows each visible blade's level, counts the blades of each
//! strip length N (one bucket per N, [`SEGMENT_BUCKETS`] of them) and bins them into
//! one list per bucket (bucket N after the buckets below it, [`bucket_base`]). One
//! indirect draw per bucket then launches mesh workgroups of [`strips_per_group`]
//! strips each: every workgroup knows its strips from its index alone, with no task
//! stage, no packing and no search. On the NVIDIA H100, which runs graphics stages on
//! a few of its SMs, the work of a task stage costs most there (performance notes,
//! attempt 12).

use crate::layout::{COUNTER_BINNED, COUNTER_STRIPS};
use crate::lod::{MAX_LEVEL, MAX_SEGMENTS, clamp_unchecked};
use spirv_std::glam::UVec3;
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
/// Buckets of strip lengths: strips of 1 to [`MAX_SEGMENTS`] segments, one indirect
/// draw each.
pub const SEGMENT_BUCKETS: u32 = MAX_SEGMENTS;

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

/// Strip length drawn by the mesh draw `draw` (its `DrawIndex`): the longest strips
/// first, which are the nearest blades (the level follows the size on screen), so the
/// depth test rejects early most fragments of the many far blades drawn after them.
pub fn draw_segments(draw: u32) -> u32 {
    SEGMENT_BUCKETS - draw
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

/// The mesh grid of bucket `segments` holding `count` strips: enough workgroups of
/// [`strips_per_group`], as (x, y, 1) no wider than [`MESH_GRID_WIDTH`], with fewer
/// than y workgroups past the last strip; (0, 0, 1) for an empty bucket.
pub fn mesh_grid(count: u32, segments: u32) -> UVec3 {
    let groups = count.div_ceil(strips_per_group(segments));
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

/// The first binned slot of bucket `segments`: the blades of the shorter strips,
/// whose counts are `counters[COUNTER_STRIPS..]` (`layout::COUNTER_STRIPS`).
pub fn bucket_base(counters: &[u32], segments: u32) -> u32 {
    let mut base = 0;
    let mut n = 1;
    while n < segments {
        base += counters[strip_counter(n)];
        n += 1;
    }
    base
}

/// The counter of bucket `segments`: blades of strips that long
/// (`counters[strip_counter(n)]`).
pub fn strip_counter(segments: u32) -> usize {
    COUNTER_STRIPS + segments as usize - 1
}

/// The counter the binning pass fills bucket `segments` with.
pub fn binned_counter(segments: u32) -> usize {
    COUNTER_BINNED + segments as usize - 1
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
    use crate::layout::COUNTER_COUNT;

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
        assert_eq!(SEGMENT_BUCKETS, 9);
        let per: Vec<u32> = (1..=SEGMENT_BUCKETS).map(strips_per_group).collect();
        assert_eq!(per, [8, 5, 4, 3, 2, 2, 2, 1, 1]);
        for n in 1..=SEGMENT_BUCKETS {
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
        const { assert!(COUNTER_BINNED + SEGMENT_BUCKETS as usize <= COUNTER_COUNT) };
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

    /// The compute pass's binning and the mesh stage's reading, run on the host:
    /// every blade lands once in its bucket, and the lanes of the bucket's
    /// workgroups write each vertex of each strip once.
    #[test]
    fn binned_blades_are_drawn_once_each_with_their_strip() {
        let levels: Vec<f32> = (0..1000)
            .map(|i| 1.0 + (i * 7919 % 1000) as f32 / 1000.0 * (MAX_LEVEL - 1.0))
            .collect();
        let mut counters = [0u32; COUNTER_COUNT];
        for &l in &levels {
            counters[strip_counter(strip_segments(l))] += 1;
        }
        let mut binned = vec![StripBlade::default(); levels.len()];
        let mut written = vec![false; levels.len()];
        for (source, &level) in levels.iter().enumerate() {
            let n = strip_segments(level);
            let place = counters[binned_counter(n)];
            counters[binned_counter(n)] += 1;
            let slot = (bucket_base(&counters, n) + place) as usize;
            assert!(!written[slot], "slot {slot} written twice");
            written[slot] = true;
            binned[slot] = StripBlade {
                source: source as u32,
                level,
            };
        }
        assert!(written.iter().all(|&w| w));
        let mut seen = vec![0u32; levels.len()];
        let order: Vec<u32> = (0..SEGMENT_BUCKETS).map(draw_segments).collect();
        assert_eq!(order, [9, 8, 7, 6, 5, 4, 3, 2, 1], "longest strips first");
        for n in order {
            let count = counters[strip_counter(n)];
            assert_eq!(counters[binned_counter(n)], count);
            let grid = mesh_grid(count, n);
            let base = bucket_base(&counters, n);
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
