//! A bounding-volume hierarchy over a mesh's triangles, so that placing the collider
//! ball (the closest point of the surface, a ray dropped onto it) visits a few dozen
//! triangles instead of every one: the exhaustive search took about 35 ms a frame on a
//! mesh of two million triangles.
//!
//! Built top down, each node's triangles split at the median centroid along the
//! longest axis of their centroids' box (a balanced tree, no surface-area heuristic:
//! the queries are one point or one ray a frame). The answers are exactly those of
//! the exhaustive [`closest_point`](super::closest_point) and
//! [`ray_hit`](super::ray_hit): the same per-triangle arithmetic, and of equal
//! distances the lowest triangle index (property test in `tests.rs`).
//!
//! Written here rather than taken from a crate: the BVH crates at hand (`bvh`,
//! `parry3d`, `obvhs`) bring their own vector types or versions of glam, and the
//! queries must reuse this module's per-triangle tests to give the same answers.

use super::{SurfaceMesh, SurfacePoint, closest_on_mesh_triangle, ray_mesh_triangle};
use spirv_std::glam::Vec3;

/// Triangles a leaf holds at most.
const LEAF_SIZE: usize = 4;

/// One node: its box, and either its triangles (a leaf: `order[first..first + count]`)
/// or its children (`count` 0: the left child follows it, the right is at `right`).
#[derive(Clone, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    first: u32,
    count: u32,
    right: u32,
}

/// The hierarchy of one mesh; queries take the same mesh it was built from.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    nodes: Vec<Node>,
    /// Triangle indices, leaf by leaf.
    order: Vec<u32>,
}

/// A closest-point candidate: squared distance, triangle, point, weights, corners.
type Closest = (f32, usize, Vec3, Vec3, [Vec3; 3]);
/// A ray-hit candidate: ray parameter, triangle, weights, corners.
type Hit = (f32, usize, Vec3, [Vec3; 3]);

impl MeshBvh {
    /// The hierarchy over every triangle of `mesh` with all three corners.
    pub fn new(mesh: &SurfaceMesh) -> Self {
        let mut items: Vec<(u32, Vec3, Vec3, Vec3)> = (0..mesh.triangles.len())
            .filter_map(|i| {
                let [a, b, c] = mesh.corners(i)?;
                let (min, max) = (a.min(b).min(c), a.max(b).max(c));
                Some((i as u32, min, max, (a + b + c) / 3.0))
            })
            .collect();
        let mut bvh = Self::default();
        if !items.is_empty() {
            bvh.build(&mut items);
        }
        bvh.order = items.iter().map(|item| item.0).collect();
        bvh
    }

    /// Adds the node over `items` (sorted in place into leaf order) and its subtree;
    /// `first` is where `items` starts in the whole order.
    fn build_at(&mut self, items: &mut [(u32, Vec3, Vec3, Vec3)], first: usize) -> usize {
        let (min, max) = items.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), item| (lo.min(item.1), hi.max(item.2)),
        );
        let index = self.nodes.len();
        self.nodes.push(Node {
            min,
            max,
            first: first as u32,
            count: items.len() as u32,
            right: 0,
        });
        if items.len() > LEAF_SIZE {
            let (lo, hi) = items.iter().fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), item| (lo.min(item.3), hi.max(item.3)),
            );
            let extent = hi - lo;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let middle = items.len() / 2;
            items.select_nth_unstable_by(middle, |a, b| a.3[axis].total_cmp(&b.3[axis]));
            let (left, right) = items.split_at_mut(middle);
            self.nodes[index].count = 0;
            self.build_at(left, first);
            let right_index = self.build_at(right, first + middle);
            self.nodes[index].right = right_index as u32;
        }
        index
    }

    fn build(&mut self, items: &mut [(u32, Vec3, Vec3, Vec3)]) {
        self.build_at(items, 0);
    }

    /// The triangles of leaf `node`.
    fn leaf(&self, node: &Node) -> &[u32] {
        &self.order[node.first as usize..(node.first + node.count) as usize]
    }

    /// Closest point of `mesh` to `p`, with the interpolated normal there: what
    /// [`closest_point`](super::closest_point) answers.
    pub fn closest_point(&self, mesh: &SurfaceMesh, p: Vec3) -> Option<SurfacePoint> {
        let mut best: Option<Closest> = None;
        let mut stack = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0usize);
        }
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let gap = p.distance_squared(p.clamp(node.min, node.max));
            // Equal distances are still looked at: the lowest triangle index wins.
            if best.is_some_and(|(d, ..)| gap > d) {
                continue;
            }
            if node.count > 0 {
                for &i in self.leaf(node) {
                    let i = i as usize;
                    let Some((d, q, w, abc)) = closest_on_mesh_triangle(mesh, i, p) else {
                        continue;
                    };
                    if best.is_none_or(|(bd, bi, ..)| d < bd || (d == bd && i < bi)) {
                        best = Some((d, i, q, w, abc));
                    }
                }
                continue;
            }
            // The nearer child is visited first (pushed last).
            let (left, right) = (n + 1, node.right as usize);
            let near = |c: usize| {
                let child = &self.nodes[c];
                p.distance_squared(p.clamp(child.min, child.max))
            };
            if near(left) <= near(right) {
                stack.extend([right, left]);
            } else {
                stack.extend([left, right]);
            }
        }
        let (_, i, position, weights, abc) = best?;
        Some(SurfacePoint {
            position,
            normal: mesh.normal_at(i, abc, weights),
        })
    }

    /// First hit of the ray `origin + t·dir` (t > 0) with `mesh`: what
    /// [`ray_hit`](super::ray_hit) answers.
    pub fn ray_hit(&self, mesh: &SurfaceMesh, origin: Vec3, dir: Vec3) -> Option<SurfacePoint> {
        let mut best: Option<Hit> = None;
        let mut stack = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0usize);
        }
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            let Some(enter) = ray_box(origin, dir, node.min, node.max) else {
                continue;
            };
            if best.is_some_and(|(t, ..)| enter > t) {
                continue;
            }
            if node.count > 0 {
                for &i in self.leaf(node) {
                    let i = i as usize;
                    let Some((t, w, abc)) = ray_mesh_triangle(mesh, i, origin, dir) else {
                        continue;
                    };
                    if best.is_none_or(|(bt, bi, ..)| t < bt || (t == bt && i < bi)) {
                        best = Some((t, i, w, abc));
                    }
                }
                continue;
            }
            stack.extend([node.right as usize, n + 1]);
        }
        let (t, i, weights, abc) = best?;
        Some(SurfacePoint {
            position: origin + dir * t,
            normal: mesh.normal_at(i, abc, weights),
        })
    }
}

/// Where the ray `origin + t·dir` enters the box [min, max] (0 when it starts inside),
/// `None` when it misses it or the box lies behind it. Slack of a part in 10⁵ of the
/// box's size on every side: a triangle lying in a face of its box (a flat ground)
/// is hit by rays the f32 slab test would otherwise round past.
fn ray_box(origin: Vec3, dir: Vec3, min: Vec3, max: Vec3) -> Option<f32> {
    let slack = (max - min).max_element().max(1.0) * 1e-5;
    let (min, max) = (min - slack, max + slack);
    let (mut enter, mut leave) = (0.0f32, f32::INFINITY);
    for axis in 0..3 {
        let (o, d) = (origin[axis], dir[axis]);
        if d == 0.0 {
            if o < min[axis] || o > max[axis] {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((min[axis] - o) / d, (max[axis] - o) / d);
        enter = enter.max(t0.min(t1));
        leave = leave.min(t0.max(t1));
    }
    (enter <= leave).then_some(enter)
}

/// A surface with its hierarchy: what the collider ball is placed on.
#[derive(Clone, Debug, Default)]
pub struct IndexedMesh {
    /// The surface.
    pub mesh: SurfaceMesh,
    bvh: MeshBvh,
}

impl IndexedMesh {
    /// `mesh` and the hierarchy over it.
    pub fn new(mesh: SurfaceMesh) -> Self {
        let bvh = MeshBvh::new(&mesh);
        Self { mesh, bvh }
    }

    /// Closest point of the surface to `p` (see [`MeshBvh::closest_point`]).
    pub fn closest_point(&self, p: Vec3) -> Option<SurfacePoint> {
        self.bvh.closest_point(&self.mesh, p)
    }

    /// First hit of a ray with the surface (see [`MeshBvh::ray_hit`]).
    pub fn ray_hit(&self, origin: Vec3, dir: Vec3) -> Option<SurfacePoint> {
        self.bvh.ray_hit(&self.mesh, origin, dir)
    }
}
