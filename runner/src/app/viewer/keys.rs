//! The viewer's keys and mouse: the live switches, the ball, the wind impulses and the
//! camera's drag.

use super::*;

impl Running {
    /// Starts a wind impulse of `kind` at simulated `time`, at its default strength,
    /// radius and lifetime, centred where the ball touches the ground (else below the
    /// camera's target).
    pub(super) fn start_impulse(&mut self, kind: u32, time: f32) {
        let target = self.camera.target;
        let centre = self
            .ball
            .as_ref()
            .map(|b| b.contact.position)
            .or_else(|| drop_onto(&self.scene.solid, target.xz()).map(|c| c.position));
        let impulse = Impulse::of_kind(kind, centre.unwrap_or(target), time);
        let name = if kind == IMPULSE_BLAST {
            "blast"
        } else {
            "downwash"
        };
        match self.impulses.add(impulse) {
            Ok(()) => log::info!("wind impulse: a {name} at {}", impulse.centre.truncate()),
            Err(_) => log::warn!(
                "wind impulse: {MAX_IMPULSES} are blowing already; the {name} is not set off"
            ),
        }
    }

    /// A key press: the live switches.
    pub(super) fn key(&mut self, key: &Key) {
        let s = &mut self.settings;
        match key {
            Key::Named(NamedKey::ArrowLeft) => self.arrows.left = true,
            Key::Named(NamedKey::ArrowRight) => self.arrows.right = true,
            Key::Named(NamedKey::ArrowUp) => self.arrows.up = true,
            Key::Named(NamedKey::ArrowDown) => self.arrows.down = true,
            Key::Character(c) => match c.as_str() {
                "f" | "F" => {
                    self.fly.on = !self.fly.on;
                    log::info!(
                        "arrows fly the camera: {} ({} units a second)",
                        if self.fly.on { "on" } else { "off" },
                        self.fly.speed
                    );
                }
                "+" | "=" | "-" => {
                    self.fly.change_speed(c.as_str() != "-");
                    log::info!("flying speed {} units a second", self.fly.speed);
                }
                "x" | "X" => self.blow = Some(IMPULSE_BLAST),
                "r" | "R" => self.blow = Some(IMPULSE_DOWNWASH),
                "b" | "B" => {
                    self.actors.ball = !self.actors.ball;
                    log::info!("ball {}", if self.actors.ball { "on" } else { "off" });
                }
                "c" | "C" => {
                    self.actors.ball_cuts = !self.actors.ball_cuts;
                    let cuts = if self.actors.ball_cuts {
                        "cuts"
                    } else {
                        "presses"
                    };
                    log::info!("the ball {cuts} the grass");
                }
                "w" | "W" => {
                    s.wind.field = s.wind.field.next();
                    log::info!("wind: {:?}", s.wind.field);
                }
                "s" | "S" => {
                    s.shape = s.shape.next();
                    log::info!("blade shape: {:?}", s.shape);
                }
                "n" | "N" => {
                    s.look.style = s.look.style.next();
                    log::info!("look: {:?}", s.look.style);
                }
                "h" | "H" => {
                    s.look.shadows = !s.look.shadows;
                    log::info!("shadows {}", if s.look.shadows { "on" } else { "off" });
                }
                "p" | "P" => {
                    s.pipeline = s.pipeline.next();
                    log::info!("grass pipeline: {:?}", s.pipeline);
                }
                "m" | "M" => {
                    use crate::app::overlay::{aa_name, next_aa};
                    let (aa, samples) = next_aa(s.look.aa, s.look.msaa);
                    s.look.aa = aa;
                    if aa == shared::settings::Antialiasing::Msaa {
                        s.look.msaa = samples;
                    }
                    log::info!("anti-aliasing: {}", aa_name(aa, samples));
                }
                "1" | "2" | "3" | "4" => {
                    let test = c.as_str().parse::<usize>().map_or(0, |n| n - 1);
                    if let Some((name, on)) = s.cull.tests.named_mut().into_iter().nth(test) {
                        *on = !*on;
                        log::info!("{name} culling {}", if *on { "on" } else { "off" });
                    }
                }
                "l" | "L" => {
                    s.lod.on = !s.lod.on;
                    log::info!("LOD {}", if s.lod.on { "on" } else { "off" });
                }
                "v" | "V" => {
                    s.view = s.view.next();
                    log::info!("view: {:?}", s.view);
                }
                "k" | "K" => self.gpu.presenter.screenshot = true,
                "o" | "O" => {
                    self.overlay.visible = !self.overlay.visible;
                    log::info!(
                        "overlay {}",
                        if self.overlay.visible { "on" } else { "off" }
                    );
                }
                "[" | "]" | "," | "." => {
                    let wind = &mut s.wind;
                    match c.as_str() {
                        "[" => wind.strength = (wind.strength - 1.0).max(0.0),
                        "]" => wind.strength = (wind.strength + 1.0).min(100.0),
                        "," => wind.direction -= 15.0,
                        _ => wind.direction += 15.0,
                    }
                    log::info!(
                        "wind strength {:.0}, direction {:.0}°",
                        wind.strength,
                        wind.direction
                    );
                }
                _ => {}
            },
            _ => {}
        }
    }

    /// A key release: stop rolling the ball.
    pub(super) fn key_up(&mut self, key: &Key) {
        match key {
            Key::Named(NamedKey::ArrowLeft) => self.arrows.left = false,
            Key::Named(NamedKey::ArrowRight) => self.arrows.right = false,
            Key::Named(NamedKey::ArrowUp) => self.arrows.up = false,
            Key::Named(NamedKey::ArrowDown) => self.arrows.down = false,
            _ => {}
        }
    }

    pub(super) fn mouse_moved(&mut self, x: f64, y: f64) {
        if let Some((lx, ly)) = self.mouse.last {
            let (dx, dy) = ((x - lx) as f32, (y - ly) as f32);
            let pan =
                self.mouse.panning || (self.mouse.rotating && self.mouse.modifiers.shift_key());
            if pan {
                self.camera.pan(dx, dy);
            } else if self.mouse.rotating {
                self.camera.rotate(dx, dy);
            }
        }
        self.mouse.last = Some((x, y));
    }
}
