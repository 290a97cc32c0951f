//! Code of the embedding example alone (`runner/examples/embed/`), not of the grass:
//! its cube.

pub mod cube;
