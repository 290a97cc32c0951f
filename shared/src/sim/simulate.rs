//! One simulation step: forces on `v2` (gravity and wind explicit, the recovery
//! semi-implicit), then validation.

use crate::Blade;
use crate::sim::collide;
use crate::sim::forces;
use crate::sim::grid::{Nearby, Slot, collide_near};
use crate::sim::impulse::{Impulse, MAX_IMPULSES, impulses_at};
use crate::sim::validate;
use crate::sim::wind;
use spirv_std::glam::{Vec2, Vec3, Vec4};

/// Fixed simulation step in seconds: the simulation runs the same at any frame rate.
/// The recovery is taken semi-implicitly ([`semi_implicit_tip`]), so no stiffness
/// makes the step overshoot.
pub const STEP_SECONDS: f32 = 1.0 / STEPS_PER_SECOND as f32;

/// The turbulent field's gust speed by default, units a second: a fresh breeze's
/// (Beaufort 5, 8 to 10.7 m/s) travelling gusts at two thirds of the wind's speed.
pub const DEFAULT_GUST_SPEED: f32 = 6.0;

/// Fixed steps per simulated second.
pub const STEPS_PER_SECOND: u32 = 120;

/// Seconds a cut blade takes to grow back unless set (`Environment::regrow`).
pub const DEFAULT_REGROW: f32 = 30.0;

/// Most steps run in one frame (two seconds of simulated time): a frame slower than
/// that loses the excess time instead of stalling the GPU for ever longer.
pub const MAX_STEPS_PER_FRAME: u32 = 240;

/// Most steps of a frame whose blades are watched ([`simulate_watched`]): in a slower
/// frame the travel passes the watch's allowance for most blades near a collider, and
/// the collision pass would step each of them again. Such a frame hands over, before
/// its steps, the blades whose root a collider reaches (`grid::Nearby::reaches`, the
/// pipeline `layout::COLLIDERS_HAND_OVER_ROOTS`) and steps the rest without the
/// colliders.
pub const WATCHED_STEPS: u32 = 16;

/// Whether a frame of `steps` steps watches its blades ([`WATCHED_STEPS`]): the
/// runner's choice of pipeline and the pass over every blade ask the same.
pub fn watches(steps: u32) -> bool {
    steps <= WATCHED_STEPS
}

/// The forces' environment, as the frame block carries it: the paper's 4-vectors D
/// (gravity direction and acceleration) and C (gravity centre and acceleration), the
/// wind, and the scalars of the step.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Environment {
    /// Gravity direction D (xyz) and acceleration (w).
    pub gravity: Vec4,
    /// Gravity centre C (xyz) and its acceleration (w).
    pub gravity_centre: Vec4,
    /// Wind direction (xyz) and strength (w).
    pub wind: Vec4,
    /// Blend t between D (0) and C (1).
    pub centre_blend: f32,
    /// Wind field, one of `wind::WIND_*`.
    pub wind_kind: u32,
    /// Linear decay of the collision strength, per second; never negative
    /// (`Settings::trample_decay`), so that where nothing pushes, η changes only where
    /// it was above zero, all the pass over every blade writes back.
    pub strength_decay: f32,
    /// Factor on every blade's stiffness s (1: as generated).
    pub stiffness_scale: f32,
    /// Colliders in use (the first of the collider buffer).
    pub colliders: u32,
    /// Simulated time at the end of the frame's steps: when the far blades' wind pose
    /// is taken (`sway::settled`). The renderer sets it from the frame's steps.
    pub time: f32,
    /// 1: the far blades sway (`tiles::far_blade`); 0: they stand at rest.
    pub far_sway: u32,
    /// Speed in units a second at which the turbulent field's gusts travel downwind
    /// (`wind::turbulent`).
    pub gust_speed: f32,
    /// Wind impulses in use (the first of the impulse array).
    pub impulses: u32,
    /// Seconds a cut blade takes to grow back (`cut::regrown`).
    pub regrow: f32,
    /// 1 while the cut table may hold a cut not yet grown back: the blades read it
    /// (`cut::as_cut`); 0: nobody reads it.
    pub cutting: u32,
    /// Padding to the block's 16-byte alignment.
    pub pad: u32,
}

impl Default for Environment {
    /// No forces but recovery at the blades' own stiffness, no colliders.
    fn default() -> Self {
        Self {
            gravity: Vec4::ZERO,
            gravity_centre: Vec4::ZERO,
            centre_blend: 0.0,
            wind: Vec4::ZERO,
            wind_kind: 0,
            strength_decay: 0.0,
            stiffness_scale: 1.0,
            colliders: 0,
            time: 0.0,
            far_sway: 1,
            gust_speed: DEFAULT_GUST_SPEED,
            impulses: 0,
            regrow: DEFAULT_REGROW,
            cutting: 0,
            pad: 0,
        }
    }
}

impl Environment {
    /// This environment with the wind field `kind` and only the forces `held` keeps:
    /// a compute pipeline's, from its specialisation constants
    /// (`gpu::layout::SPEC_WIND_FIELD`, `SPEC_IMPULSES`, `SPEC_COLLIDERS`,
    /// `SPEC_GRAVITY_CENTRE`), so that it holds only the field it steps with, and the
    /// code of the impulses, the collisions and a gravity centre only where the frame
    /// has them.
    pub fn specialised(&self, kind: u32, held: ForcesHeld) -> Self {
        Self {
            wind_kind: kind,
            impulses: if held.impulses { self.impulses } else { 0 },
            colliders: if held.colliders { self.colliders } else { 0 },
            centre_blend: if held.centre { self.centre_blend } else { 0.0 },
            ..*self
        }
    }
}

/// Which of the frame's forces a compute pipeline holds the code of
/// ([`Environment::specialised`]): those left out are taken as absent.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct ForcesHeld {
    /// Wind impulses.
    pub impulses: bool,
    /// Sphere colliders.
    pub colliders: bool,
    /// Gravity towards a centre (`centre_blend` above 0).
    pub centre: bool,
}

/// A blade and its collision strength η.
pub type BladeState = (Blade, f32);

/// The tip after a step that moves it by `pushed` (gravity and wind times Δt, taken
/// explicitly) and pulls it towards `rest` with the recovery at `k` = rate·Δt taken
/// implicitly (backward Euler): v2' = v2 + pushed + k·(Iv2 − v2'), so
/// v2' = (v2 + pushed + k·Iv2) / (1 + k). The paper's explicit step
/// v2 + pushed + k·(Iv2 − v2) overshoots the rest position once k > 1 and grows
/// without end once k > 2; this one only ever moves a fraction k / (1 + k) < 1 of the
/// way, so a blade settles at every stiffness. For the default stiffnesses (k ≤ 0.11)
/// the two differ by k²/(1 + k) of the recovery's pull, about 1 %. Written as
/// Iv2 + (v2 + pushed − Iv2) / (1 + k): from the rest position, so that f32 rounds the
/// small offset, not the blade's world coordinates (which would leave a settled tip
/// wandering by an ulp of its coordinates over k).
pub fn semi_implicit_tip(tip: Vec3, rest: Vec3, pushed: Vec3, k: f32) -> Vec3 {
    // One division, not one per component.
    rest + (tip + pushed - rest) * (1.0 / (1.0 + k))
}

/// What a blade's steps of one frame share, computed once before them: where the
/// gravity has no centre (`Environment::centre_blend` 0), the whole gravity on it,
/// g = g_E + ¼‖g_E‖·f (paper eq. 2–4), which then depends only on the blade's
/// orientation (its front f), not on its tip; and where its colliders are found (its
/// root's slot of the grid, `grid::Nearby::around`). The rest tip is taken again at
/// each step: three multiply-adds cost the compute pass less than three more live
/// registers.
#[derive(Copy, Clone, Debug)]
pub struct StepConstants {
    /// The gravity g, when it has no centre (else recomputed at each step's tip).
    pub gravity: Vec3,
    /// Where it finds its colliders in the grid.
    pub slot: Slot,
}

impl StepConstants {
    /// The constants of `blade`'s steps under `env` among the colliders `near`.
    pub fn of(blade: &Blade, env: &Environment, near: &Nearby) -> Self {
        let slot = if env.colliders == 0 {
            Slot::default()
        } else {
            near.around(blade.root(), blade.height(), env.colliders)
        };
        Self {
            slot,
            ..Self::free(blade, env)
        }
    }

    /// The constants of `blade`'s steps under `env` with no colliders.
    pub fn free(blade: &Blade, env: &Environment) -> Self {
        let gravity = if env.centre_blend == 0.0 {
            forces::gravity_from(blade, forces::environment_gravity(env.gravity))
        } else {
            Vec3::ZERO
        };
        Self {
            gravity,
            slot: Slot::default(),
        }
    }
}

/// One step of length `dt` at time `time` (paper section 5): gravity and wind move
/// v2 explicitly, the recovery (weakened by η) semi-implicitly
/// ([`semi_implicit_tip`]), then the collisions with the colliders `near` (which grow
/// η; η decays linearly), then the three validation steps.
pub fn step(
    state: BladeState,
    env: &Environment,
    near: Nearby,
    impulses: &[Impulse; MAX_IMPULSES],
    time: f32,
    dt: f32,
) -> BladeState {
    let constants = StepConstants::of(&state.0, env, &near);
    step_with(&constants, state, env, near, impulses, time, dt)
}

/// [`step`] with the blade's [`StepConstants`] already computed.
pub fn step_with(
    constants: &StepConstants,
    (blade, strength): BladeState,
    env: &Environment,
    near: Nearby,
    impulses: &[Impulse; MAX_IMPULSES],
    time: f32,
    dt: f32,
) -> BladeState {
    let moved = forced(constants, (blade, strength), env, impulses, time, dt);
    // With no collider nothing pushes and η only decays: the displacement's length
    // is not taken (the whole dispatch takes the same branch).
    let (pushed, displacement) = if env.colliders == 0 {
        (moved, Vec3::ZERO)
    } else {
        let found = (near.colliders, near.words);
        collide_near(&moved, found, &constants.slot, env.colliders)
    };
    settled((pushed, strength), displacement, env, dt)
}

/// A step's end: η after the collisions' `displacement` (`collide::update_strength`),
/// and the pushed blade validated.
fn settled(
    (pushed, strength): BladeState,
    displacement: Vec3,
    env: &Environment,
    dt: f32,
) -> BladeState {
    let strength = collide::update_strength(strength, displacement, env.strength_decay, dt);
    (validate::validate(&pushed), strength)
}

/// The forces' part of a step ([`step`]): the blade with its tip moved by gravity and
/// wind explicitly and by the recovery (weakened by η) semi-implicitly, before the
/// collisions and the validation.
pub fn forced(
    constants: &StepConstants,
    (blade, strength): BladeState,
    env: &Environment,
    impulses: &[Impulse; MAX_IMPULSES],
    time: f32,
    dt: f32,
) -> Blade {
    // The whole dispatch takes the same branch: `centre_blend` is the frame's.
    let gravity = if env.centre_blend == 0.0 {
        constants.gravity
    } else {
        let g_env = forces::environment_gravity_with_centre(
            env.gravity,
            env.gravity_centre,
            env.centre_blend,
            blade.tip(),
        );
        forces::gravity_from(&blade, g_env)
    };
    let wi = wind_at(env, impulses, blade.root(), time);
    let pushed = (gravity + forces::wind_force(&blade, wi)) * dt;
    let k = forces::recovery_rate(&blade, strength) * env.stiffness_scale * dt;
    let tip = semi_implicit_tip(blade.tip(), forces::rest_tip(&blade), pushed, k);
    blade.with_curve(blade.guide(), tip)
}

/// The wind w_i at a blade's `root` at `time` (paper eq. 9's field) with the first
/// `env.impulses` of `impulses` added (`impulse::impulses_at`), along the ground
/// there: what the simulation steps and the settled pose (`sway`) both push with.
pub fn wind_at(
    env: &Environment,
    impulses: &[Impulse; MAX_IMPULSES],
    root: Vec3,
    time: f32,
) -> Vec3 {
    let mut wi = wind::wind_field(env.wind_kind, root, time, env.wind, env.gust_speed);
    // The whole dispatch takes the same branch: the count is the frame's.
    if env.impulses > 0 {
        let down = env.gravity.truncate();
        wi += impulses_at(impulses, env.impulses, root, time, down);
    }
    wind::along_surface(wi, root, env.gravity_centre.truncate(), env.centre_blend)
}

/// Simulated time at the start of step number `index`.
pub fn step_time(index: u32) -> f32 {
    index as f32 * STEP_SECONDS
}

/// Steps `first_step .. first_step + steps`: what the compute pass runs per frame.
/// Times come from the step index, so every split into frames computes the same.
pub fn simulate(
    state: BladeState,
    env: &Environment,
    near: Nearby,
    impulses: &[Impulse; MAX_IMPULSES],
    first_step: u32,
    steps: u32,
) -> BladeState {
    // The root, up direction and orientation do not change over the steps.
    let constants = StepConstants::of(&state.0, env, &near);
    let mut s = state;
    let mut i = 0;
    while i < steps {
        s = step_with(
            &constants,
            s,
            env,
            near,
            impulses,
            step_time(first_step + i),
            STEP_SECONDS,
        );
        i += 1;
    }
    s
}

/// [`simulate`] with no collider pushing (`env.colliders` is not read), and how far
/// the blade's tip (x) and midpoint (y) may have travelled from the first step's
/// forces on: a bound on the length of the path each took through every step's
/// forces and validation, each move counted by the sum of its coordinates' sizes
/// (|x| + |y| + |z|, never less than its length, with no square root). A point a
/// step's forces moved it to lies within that bound of where the steps leave it, so
/// [`Nearby::may_have_touched`] can ask once, after the steps, what a watch of every
/// step would have asked ([`simulate_watched`]).
pub fn simulate_travelled(
    state: BladeState,
    env: &Environment,
    impulses: &[Impulse; MAX_IMPULSES],
    first_step: u32,
    steps: u32,
) -> (BladeState, Vec2) {
    let constants = StepConstants::free(&state.0, env);
    let mut s = state;
    let mut travel = Vec2::ZERO;
    let mut i = 0;
    while i < steps {
        let moved = forced(
            &constants,
            s,
            env,
            impulses,
            step_time(first_step + i),
            STEP_SECONDS,
        );
        // The forces move only the tip, and the midpoint by a quarter of it
        // (m = ¼v0 + ½v1 + ¼v2); the path starts at the first step's forced point.
        if i > 0 {
            let forced_by = (moved.tip() - s.0.tip()).abs().element_sum();
            travel += Vec2::new(forced_by, 0.25 * forced_by);
        }
        s = settled((moved, s.1), Vec3::ZERO, env, STEP_SECONDS);
        let tip = s.0.tip() - moved.tip();
        let mid = 0.5 * (s.0.guide() - moved.guide()) + 0.25 * tip;
        travel += Vec2::new(tip.abs().element_sum(), mid.abs().element_sum());
        i += 1;
    }
    (s, travel)
}

/// [`simulate`] with no collider pushing (`env.colliders` is not read), and whether a
/// collider of `near` that pushes may have held a step's tip or midpoint as the
/// forces moved them: the test [`collide_near`] makes before any push, asked after
/// the steps of the points where they leave the blade with their travel
/// ([`simulate_travelled`], [`Nearby::may_have_touched`]). Where it says no, every
/// push of [`simulate`] with those colliders would have been zero, so the blade and
/// its strength η are what it gives, to the bit; where it says yes, the frame's
/// steps are to be run again with the colliders (the compute pass's collision pass).
pub fn simulate_watched(
    state: BladeState,
    env: &Environment,
    near: Nearby,
    impulses: &[Impulse; MAX_IMPULSES],
    first_step: u32,
    steps: u32,
) -> (BladeState, bool) {
    let (s, travel) = simulate_travelled(state, env, impulses, first_step, steps);
    (s, near.may_have_touched(&s.0, travel))
}

/// The host side of fixed steps: turns frame times into a whole number of steps and
/// the simulated time at which they start. Counts in whole steps so that any sequence
/// of frames adding up to the same time runs exactly the same steps.
#[cfg(not(target_arch = "spirv"))]
#[derive(Copy, Clone, Debug, Default)]
pub struct SimClock {
    steps_done: u32,
    accumulator: f64,
}

#[cfg(not(target_arch = "spirv"))]
impl SimClock {
    /// Advances by a frame of `frame_seconds`; returns (first step index, steps to run).
    pub fn advance(&mut self, frame_seconds: f64) -> (u32, u32) {
        // The accumulator counts steps; the epsilon keeps a sum of frame times that
        // should make a whole step (0.1 + 0.2 s) from counting as 0.9999… of one.
        self.accumulator += frame_seconds.max(0.0) * f64::from(STEPS_PER_SECOND);
        let whole = (self.accumulator + 1e-6).floor();
        let steps = (whole as u32).min(MAX_STEPS_PER_FRAME);
        let first = self.steps_done;
        self.steps_done = self.steps_done.wrapping_add(steps);
        // A frame slower than the cap drops the time it could not simulate.
        self.accumulator = (self.accumulator - f64::from(steps)).clamp(0.0, 1.0);
        (first, steps)
    }

    /// Simulated time of the next step, in seconds.
    pub fn time(&self) -> f32 {
        step_time(self.steps_done)
    }
}

#[cfg(test)]
mod tests;
