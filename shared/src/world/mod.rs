//! Where grass grows: the tiled world and its blades, the generated valley, a loaded
//! scene's surface cut into tiles, painted maps, and (host only) stored fields and
//! triangle meshes.

#[cfg(not(target_arch = "spirv"))]
pub mod generate;
#[cfg(not(target_arch = "spirv"))]
pub mod mesh;
pub mod paint;
pub mod pool;
pub mod surface;
pub mod terrain;
pub mod tiles;
