//! The mesh-shader path's blade strips and how blades are packed into mesh workgroups
//! (issue 17), after AMD's mesh-shader grass (GPUOpen, *Procedural grass rendering*,
//! 2022): no tessellator; a task workgroup takes [`TASK_BLADES`] visible blades, drops
//! those its tests leave out, and packs the rest by level of detail into meshlets of
//! at most [`MESHLET_VERTICES`] vertices, one mesh workgroup each.
//!
//! The task stage's code here has no panic path: rust-gpu turns a panic into an early
//! return, and an invocation that may return before `OpEmitMeshTasksEXT` makes
//! lavapipe (Mesa 25.0) launch nothing for the whole workgroup. So no bounds-checked
//! indexing (the indices are in range by construction) and no `clamp` (which checks
//! its bounds); a SPIR-V test checks the task modules for returns.
//!
//! A blade of level L is a strip of N = ⌈L⌉ segments: 2(N + 1) vertices and exactly
//! 2N triangles (the tessellator's fractional-odd quads make 6N − 4). Its rows lie at
//! v = j / L (the last at 1), so the last segment grows from nothing as L passes a
//! whole number: the shape morphs continuously, as fractional-odd spacing does.

use crate::lod::{MAX_LEVEL, clamp_unchecked};
use spirv_std::arch::IndexUnchecked;
use spirv_std::glam::UVec3;
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Visible blades per task workgroup (its invocations).
pub const TASK_BLADES: u32 = 32;
/// Invocations of a mesh workgroup.
pub const MESH_THREADS: u32 = 32;
/// Most vertices a meshlet holds (the mesh stage's `output_vertices`): 32, which the
/// NVIDIA H100 drew fastest of 24, 32, 64 and 128 (performance notes, attempt 11).
pub const MESHLET_VERTICES: u32 = 32;
/// Most triangles a meshlet holds (`output_primitives_ext`): a meshlet's blades have
/// 2 fewer triangles than vertices each.
pub const MESHLET_TRIANGLES: u32 = MESHLET_VERTICES - 2;
/// Largest task grid along x: the smallest `maxTaskWorkGroupCount[0]` Vulkan allows
/// is 65,535; more workgroups go on along y.
pub const TASK_GRID_WIDTH: u32 = 32_768;

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

/// (u, v) of vertex `k` of a strip at `level`: u alternates across the width (0, 1),
/// v is the row's [`strip_row`].
pub fn strip_coord(k: u32, level: f32) -> (f32, f32) {
    ((k & 1) as f32, strip_row(k >> 1, level))
}

/// Triangle `t` of a strip whose first vertex is `base`: two per segment, both
/// counter-clockwise seen from the blade's front.
pub fn strip_triangle(t: u32, base: u32) -> UVec3 {
    let row = base + 2 * (t >> 1);
    if t & 1 == 0 {
        UVec3::new(row, row + 1, row + 2)
    } else {
        UVec3::new(row + 1, row + 3, row + 2)
    }
}

/// Task workgroups for `visible` blades, as a grid (x, y, 1) no wider than
/// [`TASK_GRID_WIDTH`].
pub fn task_grid(visible: u32) -> UVec3 {
    let groups = visible.div_ceil(TASK_BLADES);
    let x = groups.min(TASK_GRID_WIDTH);
    UVec3::new(x, groups.div_ceil(x.max(1)), 1)
}

/// The visible list's slot of invocation `lane` of task workgroup `group` in a launch
/// of `groups` ([`task_grid`]'s inverse).
pub fn task_slot(group: UVec3, groups: UVec3, lane: u32) -> u32 {
    (group.y * groups.x + group.x) * TASK_BLADES + lane
}

/// What a task workgroup hands its mesh workgroups: the blades it kept, packed, and
/// where each meshlet's blades start.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BladeGroup {
    /// Per blade: the slot of the visible list (the dressed buffer's slot, or the
    /// index into the visible list).
    pub slots: [u32; TASK_BLADES as usize],
    /// Per blade: its level of detail.
    pub levels: [f32; TASK_BLADES as usize],
    /// Per blade: its strip's segments (0 when dropped).
    pub segments: [u32; TASK_BLADES as usize],
    /// Meshlet m holds the packed blades `first[m]..first[m + 1]`.
    pub first: [u32; TASK_BLADES as usize + 1],
    /// Number of meshlets, once packed.
    pub meshlets: u32,
}

impl Default for BladeGroup {
    fn default() -> Self {
        Self {
            slots: [0; TASK_BLADES as usize],
            levels: [0.0; TASK_BLADES as usize],
            segments: [0; TASK_BLADES as usize],
            first: [0; TASK_BLADES as usize + 1],
            meshlets: 0,
        }
    }
}

impl BladeGroup {
    /// Packs the first `count` blades in place: drops those of 0 segments, keeps the
    /// rest in order, and starts a new meshlet wherever the next blade's strip would
    /// pass [`MESHLET_VERTICES`]. Returns the number of meshlets (also kept in
    /// `meshlets`). One invocation runs
    /// it (at most [`TASK_BLADES`] steps).
    pub fn pack(&mut self, count: u32) -> u32 {
        let count = (count as usize).min(TASK_BLADES as usize);
        let mut kept = 0usize;
        let mut meshlets = 0usize;
        let mut used = MESHLET_VERTICES; // no meshlet open yet
        let mut i = 0usize;
        while i < count {
            // SAFETY: kept <= i < count <= TASK_BLADES, and meshlets <= kept + 1 <=
            // TASK_BLADES + 1 entries of `first`: every index is in range.
            unsafe {
                let segments = *self.segments.index_unchecked(i);
                let vertices = strip_vertices(segments);
                if vertices > 0 {
                    if used + vertices > MESHLET_VERTICES {
                        *self.first.index_unchecked_mut(meshlets) = kept as u32;
                        meshlets += 1;
                        used = 0;
                    }
                    *self.slots.index_unchecked_mut(kept) = *self.slots.index_unchecked(i);
                    *self.levels.index_unchecked_mut(kept) = *self.levels.index_unchecked(i);
                    *self.segments.index_unchecked_mut(kept) = segments;
                    kept += 1;
                    used += vertices;
                }
            }
            i += 1;
        }
        // SAFETY: meshlets <= count <= TASK_BLADES.
        unsafe { *self.first.index_unchecked_mut(meshlets) = kept as u32 };
        self.meshlets = meshlets as u32;
        self.meshlets
    }

    /// Sets blade `lane`'s entry (before [`Self::pack`]).
    pub fn set(&mut self, lane: u32, slot: u32, level: f32, segments: u32) {
        let i = (lane % TASK_BLADES) as usize;
        // SAFETY: i < TASK_BLADES, the arrays' length.
        unsafe {
            *self.slots.index_unchecked_mut(i) = slot;
            *self.levels.index_unchecked_mut(i) = level;
            *self.segments.index_unchecked_mut(i) = segments;
        }
    }
}

/// The meshlet `m` of a packed group: its blades (first, end), vertices and triangles.
pub fn meshlet_extent(group: &BladeGroup, m: u32) -> (u32, u32, u32, u32) {
    let (first, end) = (group.first[m as usize], group.first[m as usize + 1]);
    let (mut vertices, mut triangles) = (0, 0);
    let mut b = first;
    while b < end {
        let segments = group.segments[b as usize];
        vertices += strip_vertices(segments);
        triangles += 2 * segments;
        b += 1;
    }
    (first, end, vertices, triangles)
}

/// First vertex, within its meshlet, of packed blade `b` of the meshlet starting at
/// blade `first`: the vertices of the blades before it.
pub fn vertex_base(group: &BladeGroup, first: u32, b: u32) -> u32 {
    let mut base = 0;
    let mut i = first;
    while i < b {
        base += strip_vertices(group.segments[i as usize]);
        i += 1;
    }
    base
}

/// Triangles of a strip of `segments`.
pub fn strip_triangles(segments: u32) -> u32 {
    2 * segments
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Which blade of meshlet `(first, end)` owns its vertex `index` (or its triangle
    /// `index` when `triangles`): (blade, the blade's first vertex or triangle).
    fn owner(group: &BladeGroup, first: u32, end: u32, index: u32, triangles: bool) -> (u32, u32) {
        let mut base = 0;
        let mut b = first;
        while b + 1 < end {
            let segments = group.segments[b as usize];
            let n = if triangles {
                strip_triangles(segments)
            } else {
                strip_vertices(segments)
            };
            if index < base + n {
                break;
            }
            base += n;
            b += 1;
        }
        (b, base)
    }

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
    fn packing_keeps_order_drops_empty_and_fills_meshlets() {
        let mut g = BladeGroup::default();
        let segments = [9, 0, 1, 1, 5, 9, 9, 0, 3, 2];
        for (i, &s) in segments.iter().enumerate() {
            g.slots[i] = 100 + i as u32;
            g.levels[i] = s as f32;
            g.segments[i] = s;
        }
        let meshlets = g.pack(segments.len() as u32);
        let kept: Vec<u32> = (0..g.first[meshlets as usize])
            .map(|i| g.slots[i as usize])
            .collect();
        assert_eq!(kept, [100, 102, 103, 104, 105, 106, 108, 109]);
        let mut seen = 0;
        for m in 0..meshlets {
            let (first, end, vertices, triangles) = meshlet_extent(&g, m);
            assert!(end > first, "meshlet {m} empty");
            assert!(vertices <= MESHLET_VERTICES && triangles <= MESHLET_TRIANGLES);
            seen += end - first;
        }
        assert_eq!(seen, 8);
        // At most 32 vertices: 20 + 4 + 4, then 12 + 20, then 20 + 8, then 6.
        assert_eq!(MESHLET_VERTICES, 32);
        assert_eq!(meshlets, 4);
        assert_eq!(&g.first[..5], &[0, 3, 5, 7, 8]);
        // The owner of each vertex is the blade whose strip holds it.
        let (first, end, vertices, _) = meshlet_extent(&g, 0);
        let mut expect = Vec::new();
        for b in first..end {
            for k in 0..strip_vertices(g.segments[b as usize]) {
                expect.push((b, k));
            }
        }
        for (i, &(b, k)) in expect.iter().enumerate() {
            let (ob, base) = owner(&g, first, end, i as u32, false);
            assert_eq!((ob, i as u32 - base), (b, k));
        }
        assert_eq!(expect.len() as u32, vertices);
        for b in first..end {
            let (ob, base) = owner(&g, first, end, vertex_base(&g, first, b), false);
            assert_eq!((ob, base), (b, vertex_base(&g, first, b)));
        }
    }

    #[test]
    fn an_all_dropped_group_has_no_meshlets() {
        let mut g = BladeGroup::default();
        assert_eq!(g.pack(TASK_BLADES), 0);
        assert_eq!(g.first[0], 0);
    }

    #[test]
    fn task_grids_cover_every_blade_within_the_limit() {
        const { assert!(TASK_GRID_WIDTH <= 65_535) };
        for visible in [0, 1, 32, 33, 4_194_304, 40_000_000] {
            let g = task_grid(visible);
            assert!(g.x <= TASK_GRID_WIDTH);
            assert!(g.x * g.y * TASK_BLADES >= visible);
            assert!(g.x * g.y * TASK_BLADES < visible + TASK_GRID_WIDTH * TASK_BLADES);
            // The last workgroup's last invocation takes the grid's last slot.
            if visible > 0 {
                let last = task_slot(g - UVec3::new(1, 1, 0), g, TASK_BLADES - 1);
                assert_eq!(last + 1, g.x * g.y * TASK_BLADES);
            }
        }
    }
}
