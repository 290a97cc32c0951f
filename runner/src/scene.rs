//! What is simulated and drawn: the blades, the ground and the settings that fill the
//! frame's uniform block.

use crate::camera::OrbitCamera;
use glam::{UVec4, Vec3, Vec4};
use shared::Blade;
use shared::cull;
use shared::generate::{side_for, square_field};
use shared::layout::FrameUniforms;
use shared::lod::MAX_SEGMENTS;
use shared::shape::SHAPE_QUADRATIC;

/// The field: blades on a square ground.
pub struct Scene {
    /// The blades at rest.
    pub blades: Vec<Blade>,
    /// Side of the square ground.
    pub side: f32,
}

impl Scene {
    /// `count` blades on a square sized for the course density, from `seed`.
    pub fn square(count: u32, seed: u64) -> Self {
        let side = side_for(count);
        Self {
            blades: square_field(count, side, seed),
            side,
        }
    }
}

/// The settings of the simulation, culling, LOD and shading.
#[derive(Copy, Clone, Debug)]
pub struct Settings {
    /// Gravity direction (xyz) and acceleration (w).
    pub gravity: Vec4,
    /// Wind direction (xyz) and strength (w).
    pub wind: Vec4,
    /// Direction towards the light (xyz, unit) and ambient (w).
    pub light: Vec4,
    /// Orientation threshold.
    pub orientation_threshold: f32,
    /// Frustum tolerance in clip units.
    pub frustum_tolerance: f32,
    /// Distance beyond which blades are culled.
    pub max_distance: f32,
    /// Distance buckets.
    pub buckets: u32,
    /// Enabled cull tests (mask of `shared::cull::*`).
    pub cull: u32,
    /// LOD: full detail up to `lod_near`, fewest segments from `lod_far`.
    pub lod_near: f32,
    /// See `lod_near`.
    pub lod_far: f32,
    /// Fewest vertical segments, far away.
    pub lod_min: f32,
    /// Blade shape (`shared::shape::SHAPE_*`).
    pub shape: u32,
    /// Tip start k of the triangle-tip shape.
    pub tip_start: f32,
}

impl Settings {
    /// Defaults scaled to a field of side `side`.
    pub fn for_field(side: f32) -> Self {
        Self {
            gravity: Vec4::new(0.0, -1.0, 0.0, 9.8),
            wind: Vec4::new(1.0, 0.0, 0.35, 7.0),
            light: Vec3::new(0.4, 0.8, 0.3).normalize().extend(0.35),
            orientation_threshold: 0.9,
            frustum_tolerance: 0.5,
            max_distance: (side * 1.5).max(40.0),
            buckets: 8,
            cull: cull::ALL,
            lod_near: 6.0,
            lod_far: (side * 0.8).max(30.0),
            lod_min: 2.0,
            shape: SHAPE_QUADRATIC,
            tip_start: 0.5,
        }
    }

    /// The uniform block of a frame seen by `camera` on a target of `aspect`.
    pub fn uniforms(&self, camera: &OrbitCamera, aspect: f32, scene: &Scene) -> FrameUniforms {
        FrameUniforms {
            view_proj: camera.view_proj(aspect),
            camera: camera.eye().extend(1.0),
            light: self.light,
            gravity: self.gravity,
            wind: self.wind,
            cull: Vec4::new(
                self.orientation_threshold,
                self.frustum_tolerance,
                self.max_distance,
                self.buckets as f32,
            ),
            lod: Vec4::new(
                self.lod_near,
                self.lod_far,
                MAX_SEGMENTS as f32,
                self.lod_min,
            ),
            ground: Vec4::new(0.5 * scene.side + 1.0, self.tip_start, 0.0, 0.0),
            flags: UVec4::new(self.cull, self.shape, scene.blades.len() as u32, 0),
        }
    }
}
