//! The compute passes: reduce the occluders' depth into a pyramid, build the
//! colliders' grid, then simulate every blade (and cut it), cull it, count each
//! test's removals and compact the survivors, then write the indirect draw commands
//! and answer the frame's questions; after the draw, the temporal resolve.

pub mod clumps;
pub mod cut;
pub mod draws;
pub mod grid;
pub mod hiz;
pub mod query;
pub mod raster;
pub mod reference;
pub mod shade;
pub mod shadow;
pub mod simulate;
pub mod tally;
pub mod temporal;
pub mod tiles;
