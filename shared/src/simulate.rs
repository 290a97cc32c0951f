//! One simulation step: forces on `v2`, an explicit Euler step, then validation.

use crate::{Blade, forces, validate, wind};
use spirv_std::glam::Vec4;

/// Fixed simulation step in seconds. Recovery with stiffness s relaxes `v2` at rate
/// s·Δt per step; with s up to 13 an explicit step overshoots once s·Δt > 1, so the
/// step is fixed and small, independent of the frame rate.
pub const STEP_SECONDS: f32 = 1.0 / STEPS_PER_SECOND as f32;

/// Fixed steps per simulated second.
pub const STEPS_PER_SECOND: u32 = 120;

/// Most steps run in one frame (two seconds of simulated time): a frame slower than
/// that loses the excess time instead of stalling the GPU for ever longer.
pub const MAX_STEPS_PER_FRAME: u32 = 240;

/// The forces' environment: gravity D (direction xyz, acceleration w) and the wind
/// (direction xyz, strength w), as the uniform buffer carries them.
#[derive(Copy, Clone, Debug)]
pub struct Environment {
    /// Gravity direction (xyz) and acceleration (w).
    pub gravity: Vec4,
    /// Wind direction (xyz) and strength (w).
    pub wind: Vec4,
}

/// One explicit step of length `dt` at time `time`: v2 ← v2 + (g + r + w)·Δt, then the
/// three validation steps (paper sections 5.1 and 5.2).
pub fn step(blade: &Blade, env: &Environment, time: f32, dt: f32) -> Blade {
    let wi = wind::breeze(blade.root(), time, env.wind);
    let force = forces::gravity(blade, env.gravity)
        + forces::recovery(blade, 0.0)
        + forces::wind_force(blade, wi);
    let moved = blade.with_curve(blade.guide(), blade.tip() + force * dt);
    validate::validate(&moved)
}

/// Simulated time at the start of step number `index`.
pub fn step_time(index: u32) -> f32 {
    index as f32 * STEP_SECONDS
}

/// Steps `first_step .. first_step + steps`: what the compute pass runs per frame.
/// Times come from the step index, so every split into frames computes the same.
pub fn simulate(blade: &Blade, env: &Environment, first_step: u32, steps: u32) -> Blade {
    let mut b = *blade;
    let mut i = 0;
    while i < steps {
        b = step(&b, env, step_time(first_step + i), STEP_SECONDS);
        i += 1;
    }
    b
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
    use crate::glam::Vec3;

    fn env() -> Environment {
        Environment {
            gravity: Vec4::new(0.0, -1.0, 0.0, 9.8),
            wind: Vec4::new(1.0, 0.0, 0.3, 6.0),
        }
    }

    fn run(frame_seconds: f64, total: f64) -> Blade {
        let mut b = Blade::at_rest(Vec3::new(1.0, 0.0, 2.0), Vec3::Y, 0.4, 2.0, 0.12, 8.0);
        let mut clock = SimClock::default();
        let frames = (total / frame_seconds).round() as u32;
        for _ in 0..frames {
            let (t, n) = clock.advance(frame_seconds);
            b = simulate(&b, &env(), t, n);
        }
        b
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

    /// Under gravity and a strong gusty wind, every blade keeps a valid shape: its
    /// arc length stays within 5 % of h (the tips never fold back onto the roots).
    #[test]
    fn long_runs_in_strong_wind_keep_length_and_ground() {
        let windy = Environment {
            gravity: env().gravity,
            wind: Vec4::new(0.6, 0.0, 0.8, 12.0),
        };
        let mut worst: f32 = 0.0;
        for b in crate::generate::square_field(64, 8.0, 3) {
            let mut b = b;
            for frame in 0..120 {
                b = simulate(&b, &windy, frame * 5, 5);
                let (v0, up) = (b.root(), b.up_dir());
                assert!(up.dot(b.tip() - v0) >= -1e-5);
                let len = crate::validate::bezier_length(v0, b.guide(), b.tip(), 64);
                worst = worst.max((len - b.height()).abs() / b.height());
            }
        }
        assert!(worst < 0.05, "worst relative length error {worst}");
    }

    #[test]
    fn gravity_alone_bends_a_blade_but_it_stays_valid() {
        let calm = Environment {
            gravity: env().gravity,
            wind: Vec4::ZERO,
        };
        let b = Blade::at_rest(Vec3::ZERO, Vec3::Y, 0.0, 2.0, 0.1, 7.0);
        let b = simulate(&b, &calm, 0, 600);
        assert!(b.tip().is_finite());
        // It bends towards its front (−Z for θ = 0) and settles below its rest height.
        assert!(b.tip().z < -0.1 && b.tip().y < 2.0 && b.tip().y > 0.0);
    }
}
