//! The interface between the runner and the shaders: the frame's block, bindings and
//! push constants (built from every concern's parameter block, and imported by none of
//! them), and the counter buffer's words.

pub mod counters;
pub mod layout;
