//! One simulation step: forces on `v2` (gravity and wind explicit, the recovery
//! semi-implicit), then validation.

use crate::Blade;
use crate::sim::collide;
use crate::sim::forces;
use crate::sim::grid::{Nearby, Slot, collide_near};
use crate::sim::impulse::{Impulse, MAX_IMPULSES, impulses_at};
use crate::sim::validate;
use crate::sim::wind;
use spirv_std::glam::{Vec3, Vec4};

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
    /// Linear decay of the collision strength, per second.
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

/// [`simulate`] with no collider pushing (`env.colliders` is not read), watching the
/// colliders of `slot` in `near` (of the first `count`) that push: whether a step's
/// tip or midpoint, moved by the forces, came inside one's bounding sphere
/// (`Nearby::may_touch`), the test [`collide_near`] makes before any push. Where none
/// did, every push of [`simulate`] with those colliders would have been zero, so the
/// blade and its strength η are what it gives, to the bit; where one did, the frame's
/// steps are to be run again with the colliders (the compute pass's collision pass).
#[allow(clippy::too_many_arguments)]
pub fn simulate_watched(
    state: BladeState,
    env: &Environment,
    (near, slot, count): (Nearby, Slot, u32),
    impulses: &[Impulse; MAX_IMPULSES],
    first_step: u32,
    steps: u32,
) -> (BladeState, bool) {
    let constants = StepConstants::free(&state.0, env);
    let mut s = state;
    let mut touched = false;
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
        let mid = collide::fixed_midpoint(&moved) + 0.25 * moved.tip();
        touched = touched || near.may_touch(moved.tip(), mid, &slot, count);
        s = settled((moved, s.1), Vec3::ZERO, env, STEP_SECONDS);
        i += 1;
    }
    (s, touched)
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
mod tests {
    use super::*;
    use crate::sim::grid::{ColliderSet, NOTHING_NEAR};
    use crate::sim::impulse::NO_IMPULSES;

    fn env() -> Environment {
        Environment {
            gravity: Vec4::new(0.0, -1.0, 0.0, 9.8),
            wind: Vec4::new(1.0, 0.0, 0.3, 6.0),
            wind_kind: wind::WIND_BREEZE,
            strength_decay: 0.5,
            ..Default::default()
        }
    }

    /// Runs `steps` steps from rest without colliders.
    fn settle(b: Blade, env: &Environment, steps: u32) -> Blade {
        simulate((b, 0.0), env, NOTHING_NEAR, &NO_IMPULSES, 0, steps).0
    }

    fn run(frame_seconds: f64, total: f64) -> Blade {
        let mut b = Blade::at_rest(Vec3::new(1.0, 0.0, 2.0), Vec3::Y, 0.4, 2.0, 0.12, 8.0);
        let mut clock = SimClock::default();
        let frames = (total / frame_seconds).round() as u32;
        for _ in 0..frames {
            let (t, n) = clock.advance(frame_seconds);
            b = simulate((b, 0.0), &env(), NOTHING_NEAR, &NO_IMPULSES, t, n).0;
        }
        b
    }

    /// The steps watched, without the colliders' pushes, against the steps with them,
    /// under a crowd of walkers (a walker to 9 square units): a blade whose watch saw
    /// no collider's bounding sphere ends the same to the bit, and few of the blades
    /// within reach of one are touched. Measured: 3,977 of 4,096 blades within reach,
    /// 767 touched. The watch without the midpoints failed.
    #[test]
    fn a_blade_whose_watch_saw_no_collider_steps_as_with_the_colliders() {
        use crate::sim::collide::Collider;
        use crate::sim::grid::{REACH_MARGIN, fitted};
        let blades = crate::world::generate::square_field(4096, 30.0, 3);
        let walkers: Vec<Collider> = (0..100)
            .map(|i| {
                let jitter = 0.37 * (i * 7 % 5) as f32;
                let x = (i % 10) as f32 * 3.0 - 13.5 + jitter;
                let at = Vec3::new(x, 0.0, (i / 10) as f32 * 3.0 - 13.0 - jitter);
                Collider::capsule(at + Vec3::Y * 0.3, at + Vec3::Y * 1.5, 0.3)
            })
            .collect();
        let mut e = env();
        e.colliders = walkers.len() as u32;
        let reach = crate::blade::HEIGHT.1 * REACH_MARGIN;
        let set = ColliderSet::new(&walkers, fitted(&walkers, reach, 4096));
        let near = set.nearby();
        let (mut reaching, mut touched) = (0, 0);
        for b in &blades {
            // Trodden a little: η 0.3, a frame of four steps.
            let state = (*b, 0.3);
            let slot = near.around(b.root(), b.height(), e.colliders);
            let (within, cutter) = near.reaches(b.root(), b.height() * REACH_MARGIN, &slot, 100);
            assert!(!cutter);
            let watched = if within { slot } else { Slot::default() };
            let with = simulate(state, &e, near, &NO_IMPULSES, 10, 4);
            let (free, hit) =
                simulate_watched(state, &e, (near, watched, 100), &NO_IMPULSES, 10, 4);
            if !hit {
                assert_eq!(free, with, "{b:?}");
            }
            reaching += usize::from(within);
            touched += usize::from(hit);
        }
        assert!(touched > 500, "{touched} touched");
        assert!(
            3 * touched < reaching,
            "{touched} of {reaching} within reach touched"
        );
    }

    #[test]
    fn same_motion_at_2_fps_and_500_fps() {
        let slow = run(0.5, 3.0);
        let fast = run(0.002, 3.0);
        assert!(
            (slow.tip() - fast.tip()).length() < 1e-5,
            "{slow:?} vs {fast:?}"
        );
    }

    #[test]
    fn clock_counts_whole_steps_and_caps_long_frames() {
        let mut c = SimClock::default();
        let step = f64::from(STEP_SECONDS);
        assert_eq!(c.advance(step * 2.5).1, 2);
        assert_eq!(c.advance(step * 0.5).1, 1);
        assert_eq!(c.advance(100.0).1, MAX_STEPS_PER_FRAME);
        assert!(c.advance(0.0).1 <= 1);
    }

    /// Under gravity, a strong wind of each field and a ball rolling through the
    /// field, every blade keeps a valid shape: finite, v2 above its ground, arc length
    /// within 5 % of h (the tips never fold back onto the roots).
    #[test]
    fn long_runs_in_strong_wind_and_collisions_keep_length_and_ground() {
        let mut worst: f32 = 0.0;
        for kind in [wind::WIND_BREEZE, wind::WIND_GUSTS, wind::WIND_VORTEX] {
            let windy = Environment {
                wind: Vec4::new(0.6, 0.0, 0.8, 12.0),
                wind_kind: kind,
                colliders: 1,
                ..env()
            };
            for b in crate::world::generate::square_field(64, 8.0, 3) {
                let mut state = (b, 0.0);
                for frame in 0..120 {
                    // A ball crossing the field at 8 units/s.
                    let ball = Vec4::new(-4.0 + frame as f32 * 0.07, 0.8, 0.5, 1.5);
                    let set = ColliderSet::spheres(&[ball]);
                    state = simulate(state, &windy, set.nearby(), &NO_IMPULSES, frame * 5, 5);
                    let b = state.0;
                    assert!(b.v1.is_finite() && b.v2.is_finite() && state.1.is_finite());
                    let (v0, up) = (b.root(), b.up_dir());
                    assert!(up.dot(b.tip() - v0) >= -1e-5);
                    let len = crate::sim::validate::bezier_length(v0, b.guide(), b.tip(), 64);
                    worst = worst.max((len - b.height()).abs() / b.height());
                }
            }
        }
        assert!(worst < 0.05, "worst relative length error {worst}");
    }

    #[test]
    fn gravity_alone_bends_a_blade_but_it_stays_valid() {
        let calm = Environment {
            wind_kind: wind::WIND_CALM,
            ..env()
        };
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 7.0);
        let b = settle(b, &calm, 600);
        assert!(b.tip().is_finite());
        // It bends towards its front (−Z for θ = 0) and settles below its rest height.
        assert!(b.tip().z < -0.1 && b.tip().y < 2.0 && b.tip().y > 0.0);
    }

    /// A ball resting on a blade holds it down; once it leaves, η decays linearly and
    /// the blade stands back up to where the calm field alone puts it.
    #[test]
    fn a_ball_tramples_a_blade_which_recovers_after_it_leaves() {
        let calm = Environment {
            wind_kind: wind::WIND_CALM,
            strength_decay: 0.5,
            colliders: 1,
            ..env()
        };
        let rest = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.3, 2.0, 0.1, 10.0);
        let upright = settle(
            rest,
            &Environment {
                colliders: 0,
                ..calm
            },
            600,
        );
        let ball = Vec4::new(0.6, 1.2, 0.2, 1.0);
        let set = ColliderSet::spheres(&[ball]);
        let spheres = set.nearby();
        // One second under the ball.
        let (held, strength) = simulate((rest, 0.0), &calm, spheres, &NO_IMPULSES, 0, 120);
        let height = |b: &Blade| (b.tip() - b.root()).dot(b.up_dir());
        assert!(held.tip().distance(ball.truncate()) >= 1.0 - 1e-3);
        assert!(height(&held) < 0.7 * height(&upright), "{held:?}");
        assert!(strength > 0.5, "η {strength}");
        // The ball leaves: η falls at 0.5/s, so it is gone after 2 s.
        let gone = Environment {
            colliders: 0,
            ..calm
        };
        let (after, s1) = simulate((held, strength), &gone, spheres, &NO_IMPULSES, 120, 60);
        assert!(
            (s1 - (strength - 0.25)).abs() < 1e-4,
            "linear decay: {strength} → {s1}"
        );
        let (stood, s2) = simulate((after, s1), &gone, spheres, &NO_IMPULSES, 180, 600);
        assert_eq!(s2, 0.0);
        assert!((height(&stood) - height(&upright)).abs() < 1e-3);
        assert!(stood.tip().is_finite());
    }

    #[test]
    fn a_gravity_centre_pulls_blades_towards_it() {
        let planet = Environment {
            gravity: Vec4::ZERO,
            gravity_centre: Vec4::new(0.0, 0.0, 0.0, 9.8),
            centre_blend: 1.0,
            wind_kind: wind::WIND_CALM,
            ..env()
        };
        // A blade on the "south pole" of a planet of radius 5: up is −Y.
        let b = Blade::at_rest(Vec3::new(0.0, -5.0, 0.0), -Vec3::Y, 0.0, 2.0, 0.1, 7.0);
        let b = settle(b, &planet, 600);
        // Pulled back towards the centre (+Y), never through its own ground.
        assert!(b.tip().y > -7.0 + 0.05 && b.tip().y < -5.0, "{b:?}");
    }
}
