//! What is drawn (paper section 4): the four tests on each blade (orientation, view
//! frustum, distance, occlusion against a hierarchical depth pyramid), the level of
//! detail, and whether a tile of the tiled world can show a blade at all.

pub mod blade;
pub mod hiz;
pub mod lod;
pub mod tile;
