//! A scripted storm of window changes for the viewer (`--resize-storm`), so tests can
//! drive what users do by hand: resizes large and tiny, several at once, the window
//! minimised and shrunk to nothing, and back. The viewer must keep drawing through it.

/// One change to the window.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Gust {
    /// Ask for a new inner size.
    Resize(u32, u32),
    /// Ask for two sizes in a row without drawing in between.
    Burst(u32, u32),
    /// Minimise the window (the window system may ignore this, e.g. Xvfb without a
    /// window manager) and treat it as 0x0 for some ticks, then restore it.
    Minimise,
    /// Treat the window as 0x0 for some ticks, as a minimised one reports.
    Zero,
}

/// The script, run in order, one gust every [`TICKS_PER_GUST`] ticks.
pub const SCRIPT: [Gust; 12] = [
    Gust::Resize(640, 360),
    Gust::Resize(1, 1),
    Gust::Zero,
    Gust::Resize(1279, 719),
    Gust::Burst(97, 1013),
    Gust::Minimise,
    Gust::Resize(1900, 60),
    Gust::Resize(16, 16),
    Gust::Burst(2000, 1200),
    Gust::Zero,
    Gust::Resize(801, 599),
    Gust::Resize(1280, 720),
];

/// Ticks (event-loop turns) between gusts.
pub const TICKS_PER_GUST: u64 = 4;
/// Ticks a minimised or zero-sized window stays so.
pub const HIDDEN_TICKS: u64 = 6;

/// Where the storm is.
#[derive(Debug, Default)]
pub struct Storm {
    tick: u64,
    hidden_until: u64,
    /// Gusts blown so far.
    pub gusts: u64,
}

impl Storm {
    /// Advances one tick; returns the gust to apply now, if any.
    pub fn tick(&mut self) -> Option<Gust> {
        self.tick += 1;
        if self.hidden() || !self.tick.is_multiple_of(TICKS_PER_GUST) {
            return None;
        }
        let gust = SCRIPT[(self.gusts % SCRIPT.len() as u64) as usize];
        self.gusts += 1;
        if matches!(gust, Gust::Minimise | Gust::Zero) {
            self.hidden_until = self.tick + HIDDEN_TICKS;
        }
        Some(gust)
    }

    /// True while the window counts as minimised (0x0).
    pub fn hidden(&self) -> bool {
        self.tick < self.hidden_until
    }

    /// True on the tick a hidden phase ends (restore a minimised window then).
    pub fn restored(&self) -> bool {
        self.hidden_until > 0 && self.tick == self.hidden_until
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_storm_blows_the_whole_script_and_hides_for_a_while() {
        let mut storm = Storm::default();
        let mut blown = Vec::new();
        let mut hidden_ticks = 0;
        let mut restores = 0;
        while blown.len() < SCRIPT.len() {
            if let Some(g) = storm.tick() {
                blown.push(g);
            }
            hidden_ticks += u64::from(storm.hidden());
            restores += u32::from(storm.restored());
        }
        assert_eq!(blown, SCRIPT);
        // Three hidden phases (Zero, Minimise, Zero); the last still runs.
        assert!(restores >= 2, "{restores}");
        assert!(hidden_ticks >= 2 * HIDDEN_TICKS, "{hidden_ticks}");
    }
}
