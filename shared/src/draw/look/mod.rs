//! The natural look: what games add to the paper's Lambert blades. Clumps
//! and a colour palette, leaves rounded across their width and lit through, ambient
//! occlusion towards the root, fades instead of popping, a sky with a sun disc,
//! aerial perspective, sun shadows and a tone map. Every function here runs in the
//! shaders and in the host tests; `--look paper` skips all of it.
//!
//! Sources: clumps as Voronoi cells with shared lean, height and colour, rounded
//! normals and translucency follow Eric Wohllaib's *Procedural Grass in Ghost of
//! Tsushima* (GDC 2021); the sky gradient and exponential fog follow Iñigo Quilez's
//! *Better fog* (2010); the tone map is Krzysztof Narkowicz's fit of the ACES
//! reference rendering transform (2016).

pub mod clump;
pub mod coverage;
pub mod ground;
pub mod leaf;
pub mod shadow;
pub mod shadow_raster;
pub mod sky;
#[cfg(test)]
mod tests;
pub mod visibility;

use spirv_std::glam::{Mat4, Vec3};

/// Look: the paper's Lambert blades, as before (the reference images).
pub const LOOK_PAPER: u32 = 0;
/// Look: clumps, colour, rounded lit leaves, shadows, sky, fog and tone mapping.
pub const LOOK_NATURAL: u32 = 1;

/// The natural look's values, as the frame block carries them.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LookParams {
    /// World to the sun's far cascade (clip space, depth 0..1): the right half of
    /// the shadow map, over the whole shadowed region.
    pub shadow_view_proj: Mat4,
    /// World to the sun's near cascade: the left half of the shadow map, over a
    /// smaller sphere around the camera (`shadow::near_sphere`), its texels finer.
    pub near_view_proj: Mat4,
    /// `LOOK_PAPER` or `LOOK_NATURAL`.
    pub style: u32,
    /// Shadows on (1) or off (0).
    pub shadows: u32,
    /// The field's seed: clumps and colours follow it.
    pub seed: u32,
    /// Side of the shadow map in texels (filled in by the renderer, which made it).
    pub shadow_size: u32,
    /// Fog density per unit of distance (aerial perspective).
    pub fog_density: f32,
    /// Where the distance test leaves no blade: the ground takes the field's colour
    /// towards it.
    pub field_distance: f32,
    /// Size of a pixel at distance 1 (2·tan(fov/2)/height): blades are kept at least
    /// this wide times their distance, and fade instead.
    pub pixel_angle: f32,
    /// Clump size in scene units.
    pub clump_size: f32,
    /// Farthest a blade casts a shadow from the camera (beyond, its shadow is a few
    /// pixels of a few pixels' blade).
    pub caster_distance: f32,
    /// Padding to 16 bytes.
    pub padding: [u32; 4],
    /// Factor on the radiance before the tone map.
    pub exposure: f32,
    /// Height of the ground plane that carries the field to the horizon.
    pub ground_level: f32,
    /// 1 where the scene is a ground under a sky (not a planet): below the horizon
    /// the tone map draws the field from afar on the plane at `ground_level`.
    pub ground_to_horizon: u32,
}

/// Sun radiance (linear, before exposure).
pub const SUN: Vec3 = Vec3::new(2.6, 2.45, 2.2);
/// Sky light on a surface facing up (linear, before exposure).
pub const SKY_AMBIENT: Vec3 = Vec3::new(0.42, 0.55, 0.75);
