//! Local wind impulses: events with a place, a start and a lifetime that add to the
//! wind field where and while they act. A **blast** (an explosion) sends a front
//! outward from its centre; each blade is thrown away from the centre as the front
//! reaches it, and the push dies away after. A **downwash** (a rotor hovering) blows
//! outward from the point below it for its whole life, strongest part-way out and
//! pulsing in rings that travel outward, as the air a rotor drives down spreads along
//! the ground. Both push along the ground, away from the centre, so
//! [`crate::sim::wind::along_surface`] and the wind force take them as they take the
//! field; the simulation steps and the far blades' settled pose
//! ([`crate::sim::sway`]) read the sum through [`crate::sim::simulate::wind_at`].

use spirv_std::glam::{Vec3, Vec4, Vec4Swizzles};
#[cfg(target_arch = "spirv")]
use spirv_std::num_traits::Float;

/// Impulses a frame carries at most (`gpu::layout::FrameUniforms::impulses`).
pub const MAX_IMPULSES: usize = 8;

/// [`Impulse::kind`]: an explosion's front travelling outward.
pub const IMPULSE_BLAST: u32 = 0;
/// [`Impulse::kind`]: a rotor's steady outflow along the ground.
pub const IMPULSE_DOWNWASH: u32 = 1;

/// A blast's strength, radius and lifetime where none are given (the viewer's X key,
/// `--impulse blast,x,z,start`): eight times the default wind over eight units, for
/// two and a half seconds.
pub const BLAST_DEFAULT: (f32, f32, f32) = (60.0, 8.0, 2.5);
/// A downwash's strength, radius and lifetime where none are given (the viewer's R
/// key, `--impulse downwash,x,z,start`).
pub const DOWNWASH_DEFAULT: (f32, f32, f32) = (30.0, 6.0, 8.0);

/// Share of a blast's lifetime its front takes to cross its radius.
pub const BLAST_FRONT_SHARE: f32 = 0.2;
/// Share of a blast's lifetime over which the push at a point falls by a factor e
/// once the front has passed it.
pub const BLAST_DECAY_SHARE: f32 = 0.15;
/// Longest fade in or out of a downwash, seconds (at most a quarter of its life).
pub const DOWNWASH_RAMP_SECONDS: f32 = 0.5;
/// A downwash's pulses a second.
pub const DOWNWASH_PULSE_HZ: f32 = 2.0;
/// Distance between a downwash's rings, units: they travel outward at
/// `DOWNWASH_PULSE_HZ * DOWNWASH_RING_SPACING` units a second.
pub const DOWNWASH_RING_SPACING: f32 = 1.5;
/// How much a downwash's pulses vary its push (±).
pub const DOWNWASH_PULSE_SWING: f32 = 0.35;

/// An impulse array with none in use.
pub const NO_IMPULSES: [Impulse; MAX_IMPULSES] = [Impulse {
    centre: Vec4::ZERO,
    strength: 0.0,
    radius: 0.0,
    lifetime: 0.0,
    kind: 0,
}; MAX_IMPULSES];

/// One impulse, as the frame block carries it (std430: 32 bytes).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Impulse {
    /// Centre (xyz): the blast's, or the ground below the rotor; simulated time in
    /// seconds at which it starts (w).
    pub centre: Vec4,
    /// Peak acceleration, as the wind's strength.
    pub strength: f32,
    /// Distance from the centre it reaches, units.
    pub radius: f32,
    /// Seconds from its start to its end.
    pub lifetime: f32,
    /// [`IMPULSE_BLAST`] or [`IMPULSE_DOWNWASH`].
    pub kind: u32,
}

impl Impulse {
    /// A `kind` impulse centred at `centre` from simulated time `start`.
    pub fn new(
        kind: u32,
        centre: Vec3,
        start: f32,
        strength: f32,
        radius: f32,
        lifetime: f32,
    ) -> Self {
        Self {
            centre: centre.extend(start),
            strength,
            radius,
            lifetime,
            kind,
        }
    }

    /// A `kind` impulse at its default strength, radius and lifetime
    /// ([`BLAST_DEFAULT`], [`DOWNWASH_DEFAULT`]).
    pub fn of_kind(kind: u32, centre: Vec3, start: f32) -> Self {
        let (strength, radius, lifetime) = if kind == IMPULSE_BLAST {
            BLAST_DEFAULT
        } else {
            DOWNWASH_DEFAULT
        };
        Self::new(kind, centre, start, strength, radius, lifetime)
    }

    /// What makes it unusable, if anything: a centre or start not finite, a strength
    /// not finite or below 0, a radius or lifetime not above 0 or not finite, an
    /// unknown kind.
    pub fn problem(&self) -> Option<&'static str> {
        if !self.centre.is_finite() {
            Some("its centre and start must be finite")
        } else if !self.strength.is_finite() || self.strength < 0.0 {
            Some("its strength must be finite and at least 0")
        } else if !self.radius.is_finite() || self.radius <= 0.0 {
            Some("its radius must be finite and above 0")
        } else if !self.lifetime.is_finite() || self.lifetime <= 0.0 {
            Some("its lifetime must be finite and above 0")
        } else if self.kind > IMPULSE_DOWNWASH {
            Some("its kind must be a blast or a downwash")
        } else {
            None
        }
    }

    /// Simulated time at which it starts.
    pub fn start(&self) -> f32 {
        self.centre.w
    }

    /// Whether it has ended by simulated `time`.
    pub fn ended(&self, time: f32) -> bool {
        time >= self.start() + self.lifetime
    }

    /// Its push at `p` and simulated `time`, an acceleration along the ground (the
    /// plane across `down`, the gravity's unit direction, or the whole of `p − centre`
    /// where `down` is zero), away from the centre: `strength · s(d / radius) ·
    /// e(τ, d)` for d the distance along the ground and τ the time since the start,
    /// zero from the radius out and outside 0 ≤ τ < lifetime.
    /// - Blast: s(x) = (1 − x²)²; the front reaches d at τ_d = `BLAST_FRONT_SHARE` ·
    ///   lifetime · d / radius, and e = exp(−(τ − τ_d) / (`BLAST_DECAY_SHARE` ·
    ///   lifetime)) · (1 − τ / lifetime) from then on (0 before).
    /// - Downwash: s(x) = x(1 − x²)² / s_max, peaking at 1 where x = 1/√5; e = the
    ///   smoothstep of min(τ, lifetime − τ) over `DOWNWASH_RAMP_SECONDS` (at most a
    ///   quarter of the life) times 1 + `DOWNWASH_PULSE_SWING` · sin 2π(f·τ − d / λ),
    ///   rings travelling outward.
    pub fn push(&self, p: Vec3, time: f32, down: Vec3) -> Vec3 {
        let tau = time - self.start();
        if tau < 0.0 || tau >= self.lifetime || self.radius <= 0.0 {
            return Vec3::ZERO;
        }
        let r = p - self.centre.xyz();
        let r = r - down * r.dot(down);
        let d = r.length();
        let x = d / self.radius;
        if x >= 1.0 || d < 1e-5 {
            return Vec3::ZERO;
        }
        let amount = if self.kind == IMPULSE_BLAST {
            blast(x, tau, self.lifetime)
        } else {
            downwash(x, d, tau, self.lifetime)
        };
        r * (self.strength * amount / d)
    }
}

/// A blast's share of its strength at `x` of its radius, `tau` seconds after its start
/// ([`Impulse::push`]).
fn blast(x: f32, tau: f32, lifetime: f32) -> f32 {
    let since = tau - BLAST_FRONT_SHARE * lifetime * x;
    if since < 0.0 {
        return 0.0;
    }
    let fall = 1.0 - x * x;
    fall * fall * (-since / (BLAST_DECAY_SHARE * lifetime)).exp() * (1.0 - tau / lifetime)
}

/// The largest of x(1 − x²)² over 0..1, at x = 1/√5: the downwash's profile divided by
/// it peaks at 1.
const DOWNWASH_PEAK: f32 = 0.286_216_5;

/// A downwash's share of its strength at `x` of its radius (`d` units out), `tau`
/// seconds after its start ([`Impulse::push`]).
fn downwash(x: f32, d: f32, tau: f32, lifetime: f32) -> f32 {
    let fall = 1.0 - x * x;
    let profile = x * fall * fall / DOWNWASH_PEAK;
    let ramp = DOWNWASH_RAMP_SECONDS.min(0.25 * lifetime);
    let e = ((tau.min(lifetime - tau)) / ramp).clamp(0.0, 1.0);
    let envelope = e * e * (3.0 - 2.0 * e);
    let phase = DOWNWASH_PULSE_HZ * tau - d / DOWNWASH_RING_SPACING;
    let pulse = 1.0 + DOWNWASH_PULSE_SWING * (core::f32::consts::TAU * phase).sin();
    profile * envelope * pulse
}

/// The sum of the first `count` of `impulses` at `p` and `time` ([`Impulse::push`]).
pub fn impulses_at(
    impulses: &[Impulse; MAX_IMPULSES],
    count: u32,
    p: Vec3,
    time: f32,
    down: Vec3,
) -> Vec3 {
    let mut sum = Vec3::ZERO;
    let n = count.min(MAX_IMPULSES as u32) as usize;
    let mut i = 0;
    while i < n {
        sum += impulses[i].push(p, time, down);
        i += 1;
    }
    sum
}

/// The impulses live at once, as a host keeps them between frames: added as they
/// happen, dropped once ended.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct Impulses {
    all: [Impulse; MAX_IMPULSES],
    live: u32,
}

impl Impulses {
    /// Adds `impulse`; refused (handed back) when `MAX_IMPULSES` are live.
    pub fn add(&mut self, impulse: Impulse) -> Result<(), Impulse> {
        let n = self.live as usize;
        if n == MAX_IMPULSES {
            return Err(impulse);
        }
        self.all[n] = impulse;
        self.live += 1;
        Ok(())
    }

    /// Drops those that have ended by simulated `time`, keeping the others' order.
    pub fn retire(&mut self, time: f32) {
        let mut kept = 0;
        let mut i = 0;
        while i < self.live as usize {
            if !self.all[i].ended(time) {
                self.all[kept] = self.all[i];
                kept += 1;
            }
            i += 1;
        }
        while i > kept {
            i -= 1;
            self.all[i] = Impulse::default();
        }
        self.live = kept as u32;
    }

    /// All slots (the first [`Self::live`] in use), as the frame block holds them.
    pub fn slots(&self) -> &[Impulse; MAX_IMPULSES] {
        &self.all
    }

    /// How many are live.
    pub fn live(&self) -> u32 {
        self.live
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOWN: Vec3 = Vec3::new(0.0, -1.0, 0.0);

    fn blast_at_origin() -> Impulse {
        Impulse::new(IMPULSE_BLAST, Vec3::ZERO, 1.0, 40.0, 10.0, 2.0)
    }

    /// The front reaches 5 units (half the radius) at 0.2 · 2 · 0.5 = 0.2 s after the
    /// start: nothing before, then (1 − ¼)² · 40 = 22.5 times the decay since and the
    /// fade (1 − τ/2), away from the centre and along the ground.
    #[test]
    fn a_blast_throws_each_point_outward_as_its_front_arrives() {
        let b = blast_at_origin();
        let p = Vec3::new(3.0, 0.7, 4.0);
        assert_eq!(b.push(p, 1.19, DOWN), Vec3::ZERO);
        let at = b.push(p, 1.23, DOWN);
        let expected = 22.5 * (-0.03f32 / 0.3).exp() * (1.0 - 0.23 / 2.0);
        assert!(
            (at.length() - expected).abs() < 1e-3,
            "{at} against {expected}"
        );
        assert!((at.normalize() - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-5);
        // 0.3 s later it has fallen by exp(-0.3 / 0.3) and the fade.
        let later = b.push(p, 1.5, DOWN).length();
        let expected = 22.5 * (-1.0f32).exp() * (1.0 - 0.5 / 2.0);
        assert!(
            (later - expected).abs() < 1e-3,
            "{later} against {expected}"
        );
    }

    #[test]
    fn an_impulse_acts_only_inside_its_radius_and_its_life() {
        for kind in [IMPULSE_BLAST, IMPULSE_DOWNWASH] {
            let i = Impulse {
                kind,
                ..blast_at_origin()
            };
            let inside = Vec3::new(2.0, 0.0, 1.0);
            assert_eq!(i.push(inside, 0.99, DOWN), Vec3::ZERO);
            assert_eq!(i.push(inside, 3.0, DOWN), Vec3::ZERO);
            assert_eq!(i.push(Vec3::new(10.0, 0.0, 0.1), 1.5, DOWN), Vec3::ZERO);
            assert_ne!(i.push(inside, 1.5, DOWN), Vec3::ZERO);
            assert!(i.ended(3.0) && !i.ended(2.99));
        }
    }

    /// At 1/√5 of the radius, a whole second into a 4-second downwash (past its
    /// half-second fade-in), with the pulse at a zero crossing: the full strength.
    #[test]
    fn a_downwash_peaks_part_way_out_at_full_strength() {
        let w = Impulse::new(
            IMPULSE_DOWNWASH,
            Vec3::new(1.0, 5.0, 1.0),
            0.0,
            30.0,
            10.0,
            4.0,
        );
        let d = 10.0 / 5.0f32.sqrt();
        // The phase 2·τ − d/1.5 a whole number: τ = (d / 1.5 + 3) / 2.
        let tau = (d / DOWNWASH_RING_SPACING + 3.0) / DOWNWASH_PULSE_HZ;
        let p = Vec3::new(1.0 + d, 0.0, 1.0);
        let at = w.push(p, tau, DOWN);
        assert!((at - Vec3::new(30.0, 0.0, 0.0)).length() < 1e-2, "{at}");
        let mut peak: f32 = 0.0;
        for k in 1..100 {
            let x = k as f32 / 100.0;
            peak = peak.max(x * (1.0 - x * x) * (1.0 - x * x));
        }
        assert!((peak - DOWNWASH_PEAK).abs() < 1e-4);
        // Fading in: a quarter of the ramp in, smoothstep(¼) = 5/32 of that.
        let early = w.push(p, 0.125, DOWN).length();
        let phase = DOWNWASH_PULSE_HZ * 0.125 - d / DOWNWASH_RING_SPACING;
        let pulse = 1.0 + DOWNWASH_PULSE_SWING * (core::f32::consts::TAU * phase).sin();
        assert!((early - 30.0 * 5.0 / 32.0 * pulse).abs() < 1e-2, "{early}");
    }

    #[test]
    fn impulses_add_up_and_end_in_turn() {
        let mut set = Impulses::default();
        let a = blast_at_origin();
        let b = Impulse::new(
            IMPULSE_DOWNWASH,
            Vec3::new(4.0, 0.0, 0.0),
            0.5,
            20.0,
            6.0,
            10.0,
        );
        set.add(a).unwrap();
        set.add(b).unwrap();
        let p = Vec3::new(2.0, 0.0, 1.0);
        let sum = impulses_at(set.slots(), set.live(), p, 1.5, DOWN);
        assert!((sum - a.push(p, 1.5, DOWN) - b.push(p, 1.5, DOWN)).length() < 1e-5);
        assert_eq!(
            impulses_at(set.slots(), 1, p, 1.5, DOWN),
            a.push(p, 1.5, DOWN)
        );
        set.retire(3.0);
        assert_eq!(set.live(), 1);
        assert_eq!(set.slots()[0], b);
        assert_eq!(set.slots()[1], Impulse::default());
        for _ in 1..MAX_IMPULSES {
            set.add(a).unwrap();
        }
        assert_eq!(set.add(b), Err(b));
    }

    #[test]
    fn every_impulse_is_bounded_and_finite() {
        for kind in [IMPULSE_BLAST, IMPULSE_DOWNWASH] {
            let i = Impulse::new(kind, Vec3::ZERO, 0.0, 25.0, 8.0, 3.0);
            for step in 0..400 {
                let t = step as f32 * 0.01;
                for k in 0..64 {
                    let p = Vec3::new((k % 8) as f32 - 3.5, 0.3, (k / 8) as f32 * 1.1 - 4.0);
                    let w = i.push(p, t, DOWN);
                    assert!(w.is_finite() && w.length() <= 25.0 * 1.36, "{w} at {p} {t}");
                    assert!(w.y.abs() < 1e-6);
                }
            }
            // At the centre itself there is no way outward: no push.
            assert_eq!(i.push(Vec3::new(0.0, 2.0, 0.0), 1.0, DOWN), Vec3::ZERO);
        }
    }
}
