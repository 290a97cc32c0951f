//! The simulation (paper section 5): the three forces on a blade's tip, the wind
//! field and its local impulses (a blast, a downwash), collisions with spheres,
//! capsules and boxes (found through a spatial grid), cutting and regrowth, the
//! validation of the new state, one whole step, and the closed-form pose of the far
//! blades nobody simulates.

pub mod collide;
#[cfg(not(target_arch = "spirv"))]
pub mod colliders;
pub mod cut;
pub mod forces;
pub mod grid;
pub mod impulse;
pub mod simulate;
pub mod sway;
pub mod validate;
pub mod watch;
pub mod wind;
