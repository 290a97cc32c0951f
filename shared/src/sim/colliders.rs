//! A frame's colliders with their grid and watch built on the host: the grid a
//! frame's colliders need ([`fitted`]) and the same slots, bits and marks the GPU's
//! build (`compute::grid`) writes ([`ColliderSet`]), for the host's steps and the
//! tests.

use crate::sim::collide::{Collider, MAX_COLLIDERS};
use crate::sim::grid::{ColliderGrid, GRID_CORNERS, GRID_SLOTS, Nearby, mark_collider};
use crate::sim::watch::{WATCH_ALLOWANCE, WATCH_MARGIN, watch_on_host};
use spirv_std::glam::UVec4;

impl ColliderGrid {
    /// The grid of the most slots ([`GRID_SLOTS`]): the words of the renderer's buffer.
    pub fn largest() -> Self {
        Self {
            slots: GRID_SLOTS,
            ..Self::default()
        }
    }
}

/// The grid a frame's colliders need: cubes half as large as the largest collider's
/// bounds grown by `reach` on every side, and 64 slots a collider (about seven for
/// each cube it marks on a flat field, [`ColliderGrid::over_roots`]), a power of two
/// from 64 to `most`.
pub fn fitted(colliders: &[Collider], reach: f32, most: u32) -> ColliderGrid {
    let largest = colliders
        .iter()
        .map(|c| {
            let (lo, hi) = c.bounds();
            (hi - lo).max_element()
        })
        .fold(0.0f32, f32::max);
    let wanted = (colliders.len() as u32)
        .saturating_mul(64)
        .next_power_of_two();
    // A little over, so a collider exactly two cubes wide marks three at most.
    let cell = |grow: f32| (0.5 * (largest + 2.0 * grow) * 1.001).max(0.01);
    ColliderGrid {
        cell: cell(reach),
        reach,
        slots: wanted.max(64).min(most.max(1)),
        watch_cell: cell(WATCH_ALLOWANCE + WATCH_MARGIN),
        ..ColliderGrid::default()
    }
}

/// Colliders and their grid built on the host: the same slots the GPU builds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColliderSet {
    /// The colliders.
    pub colliders: Vec<Collider>,
    /// The grid.
    pub grid: ColliderGrid,
    /// Its slots' words, four at a time ([`Nearby::shapes`]; [`Self::words`] one at
    /// a time).
    pub shapes: Vec<UVec4>,
}

impl ColliderSet {
    /// `colliders` (the first [`MAX_COLLIDERS`]) in `grid`.
    pub fn new(colliders: &[Collider], grid: ColliderGrid) -> Self {
        let colliders = colliders[..colliders.len().min(MAX_COLLIDERS)].to_vec();
        // The grid's words are a whole number of four (`ColliderGrid::watch_start`).
        let mut shapes = vec![UVec4::ZERO; grid.words() / 4];
        let words: &mut [u32] = bytemuck::cast_slice_mut(&mut shapes);
        for (i, c) in colliders.iter().enumerate() {
            for corner in 0..GRID_CORNERS {
                let (marks, cube) = grid.corner_cube(c, corner);
                if marks {
                    mark_collider(words, grid.slot_base(cube), i, |w, bit| *w |= bit);
                }
                watch_on_host(words, &grid, c, corner);
            }
        }
        Self {
            colliders,
            grid,
            shapes,
        }
    }

    /// Its slots' words.
    pub fn words(&self) -> &[u32] {
        bytemuck::cast_slice(&self.shapes)
    }

    /// Every collider tested by every blade (one slot).
    pub fn every(colliders: &[Collider]) -> Self {
        Self::new(colliders, ColliderGrid::default())
    }

    /// Spheres (centre xyz, radius w), every one tested.
    pub fn spheres(spheres: &[spirv_std::glam::Vec4]) -> Self {
        let colliders: Vec<Collider> = spheres.iter().map(|s| Collider::from_sphere(*s)).collect();
        Self::every(&colliders)
    }

    /// What the blades' steps read.
    pub fn nearby(&self) -> Nearby<'_> {
        Nearby {
            colliders: &self.colliders,
            words: self.words(),
            shapes: &self.shapes,
            grid: self.grid,
        }
    }
}
