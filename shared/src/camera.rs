//! The camera as the shaders see it.

use spirv_std::glam::{Mat4, Vec3};

/// The camera, as the shaders see it.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CameraParams {
    /// World to clip space (Vulkan: y down, depth 0..1).
    pub view_proj: Mat4,
    /// Camera position in world space.
    pub position: Vec3,
    /// Focal length in pixels (`lod::focal_pixels`): an object of size s at distance
    /// d covers s · focal / d pixels.
    pub focal_pixels: f32,
}
