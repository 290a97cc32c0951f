//! How a blade becomes pixels: its surface and shape function (paper section 6), the
//! paper's shading, the natural look, the mesh path's strips, the compute rasterizer
//! of far blades, the temporal anti-aliasing, and the triangle-throughput reference.

pub mod look;
pub mod meshlet;
pub mod raster;
pub mod reference;
pub mod shade;
pub mod shape;
pub mod temporal;
