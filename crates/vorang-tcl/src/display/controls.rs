//! The viewer's controls: Tk's mouse and key events as the viewer reads them, and what the keys
//! do to the method (1–4 choose it, + and − its brightness).

use super::orbit::{Orbit, ZOOM_STEP};
use crate::tcl::Interp;
use vorang::render::Method;
use vorang::render::approx::{Exact, InterpolateCoeff, InterpolateColor, Test};

/// Brightness factor per `+` or `−`.
pub const BRIGHTNESS_STEP: f64 = 1.25;

/// What an input asks the viewer to do beyond changing the view or method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    None,
    /// The view or method changed: render again.
    Moved,
    /// `s`: save the refined image.
    Save,
    /// `p`: print the commands.
    Print,
    /// `q`, Escape, or closing the window.
    Quit,
}

/// The state between events: where a drag started and whether it pans (shift) or turns.
#[derive(Debug, Default)]
pub struct Controls {
    drag: Option<(f64, f64, bool)>,
}

impl Controls {
    /// Applies one input to the view and the method.
    pub fn apply(&mut self, input: Input, orbit: &mut Orbit, method: &mut Method) -> Action {
        match input {
            Input::Press { x, y, shift } => self.drag = Some((x, y, shift)),
            Input::Motion { x, y } => {
                let Some((x0, y0, pan)) = self.drag else {
                    return Action::None;
                };
                if pan {
                    orbit.pan(x - x0, y - y0);
                } else {
                    orbit.rotate(x - x0, y - y0);
                }
                self.drag = Some((x, y, pan));
                return Action::Moved;
            }
            Input::Release => self.drag = None,
            Input::Wheel(delta) => {
                orbit.zoom_by(ZOOM_STEP.powf(delta / 120.0));
                return Action::Moved;
            }
            Input::Key(k) => {
                return match k.as_str() {
                    "1" | "2" | "3" | "4" => match method_for_key(k.parse().unwrap_or(0), method) {
                        Some(m) => {
                            *method = m;
                            Action::Moved
                        }
                        None => Action::None,
                    },
                    "plus" | "equal" | "KP_Add" => {
                        *method = scale_brightness(method, BRIGHTNESS_STEP);
                        Action::Moved
                    }
                    "minus" | "underscore" | "KP_Subtract" => {
                        *method = scale_brightness(method, 1.0 / BRIGHTNESS_STEP);
                        Action::Moved
                    }
                    "r" => {
                        orbit.reset();
                        Action::Moved
                    }
                    "s" => Action::Save,
                    "p" => Action::Print,
                    "q" | "Escape" => Action::Quit,
                    _ => Action::None,
                };
            }
        }
        Action::None
    }
}

/// What the user asked for, from one Tk event (as the window's bindings record it:
/// `press x y state`, `motion x y`, `release`, `wheel delta`, `key keysym`).
pub enum Input {
    Press { x: f64, y: f64, shift: bool },
    Motion { x: f64, y: f64 },
    Release,
    Wheel(f64),
    Key(String),
}

pub fn parse_event(interp: &Interp, text: &str) -> Option<Input> {
    let w = interp.split_list(text).ok()?;
    let num = |i: usize| w.get(i).and_then(|v| v.parse::<f64>().ok());
    Some(match w.first()?.as_str() {
        "press" => Input::Press {
            x: num(1)?,
            y: num(2)?,
            // Tk's state bit 0 is Shift.
            shift: num(3)? as u32 & 1 != 0,
        },
        "motion" => Input::Motion {
            x: num(1)?,
            y: num(2)?,
        },
        "release" => Input::Release,
        "wheel" => Input::Wheel(num(1)?),
        "key" => Input::Key(w.get(1)?.clone()),
        _ => return None,
    })
}

/// Method `n` of the keys 1–4 (the thesis's order, most exact first), keeping the brightness
/// and integration rule of `current` where it has them: 1 `exact` (rule, step 0: one piece per
/// cell, cut at the maps' breakpoints), 2 `interpolateCoeff`, 3 `interpolateColor`, 4 `test`.
pub fn method_for_key(n: u32, current: &Method) -> Option<Method> {
    let (rule, brightness) = match current {
        Method::Exact(m) => (m.rule, m.brightness),
        Method::InterpolateCoeff(m) => (m.rule, m.brightness),
        Method::InterpolateColor(m) => (default_rule(), m.brightness),
        Method::Test(_) => (default_rule(), 1.0),
    };
    Some(match n {
        1 => Method::Exact(Exact {
            rule,
            step: 0.0,
            brightness,
        }),
        2 => Method::InterpolateCoeff(InterpolateCoeff { rule, brightness }),
        3 => Method::InterpolateColor(InterpolateColor { brightness }),
        4 => match current {
            Method::Test(t) => Method::Test(*t),
            _ => Method::Test(Test { opacity: 0.5 }),
        },
        _ => return None,
    })
}

fn default_rule() -> &'static vorang::integrate::RuleInfo {
    vorang::integrate::find("linear").unwrap_or(&vorang::integrate::RULES[0])
}

/// `current` with its brightness times `factor` (`test`: its opacity, kept in 0…1).
pub fn scale_brightness(current: &Method, factor: f64) -> Method {
    let mut m = *current;
    match &mut m {
        Method::Exact(e) => e.brightness *= factor,
        Method::InterpolateCoeff(c) => c.brightness *= factor,
        Method::InterpolateColor(c) => c.brightness *= factor,
        Method::Test(t) => t.opacity = (t.opacity * factor).clamp(0.0, 1.0),
    }
    m
}

/// The brightness of the preview (`interpolateColor`) for `current`.
pub fn brightness(current: &Method) -> f64 {
    match current {
        Method::Exact(m) => m.brightness,
        Method::InterpolateCoeff(m) => m.brightness,
        Method::InterpolateColor(m) => m.brightness,
        Method::Test(_) => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vorang::session::method_command;

    #[test]
    fn drags_turn_or_pan_and_keys_act() {
        let vol = vorang::volume::jittered_box(48, 0.0, 1);
        let view = vorang::scene::View::default();
        let mut orbit = Orbit::new(&view, &vol, 100, 100).unwrap();
        let mut method = Method::parse(&["interpolateColor", "1"]).unwrap();
        let mut c = Controls::default();
        let motion = Input::Motion { x: 20.0, y: 10.0 };
        // A move without a pressed button does nothing.
        assert_eq!(c.apply(motion, &mut orbit, &mut method), Action::None);
        let press = Input::Press {
            x: 10.0,
            y: 10.0,
            shift: false,
        };
        c.apply(press, &mut orbit, &mut method);
        let moved = Input::Motion { x: 20.0, y: 10.0 };
        assert_eq!(c.apply(moved, &mut orbit, &mut method), Action::Moved);
        assert!(orbit.rotation().is_some());
        c.apply(Input::Release, &mut orbit, &mut method);
        let shift = Input::Press {
            x: 0.0,
            y: 0.0,
            shift: true,
        };
        c.apply(shift, &mut orbit, &mut method);
        let turned = orbit.rotation();
        c.apply(Input::Motion { x: 5.0, y: 0.0 }, &mut orbit, &mut method);
        assert_eq!(
            orbit.rotation(),
            turned,
            "shift-drag pans, it does not turn"
        );
        assert!(orbit.view().look_at.eye[0] < 0.0);
        let key = |k: &str| Input::Key(k.into());
        assert_eq!(c.apply(key("plus"), &mut orbit, &mut method), Action::Moved);
        assert_eq!(brightness(&method), 1.25);
        assert_eq!(c.apply(key("2"), &mut orbit, &mut method), Action::Moved);
        assert_eq!(method.name(), "interpolateCoeff");
        assert_eq!(c.apply(key("s"), &mut orbit, &mut method), Action::Save);
        assert_eq!(c.apply(key("p"), &mut orbit, &mut method), Action::Print);
        assert_eq!(c.apply(key("x"), &mut orbit, &mut method), Action::None);
        assert_eq!(c.apply(key("r"), &mut orbit, &mut method), Action::Moved);
        assert_eq!(orbit.rotation(), None);
        assert_eq!(c.apply(key("q"), &mut orbit, &mut method), Action::Quit);
    }

    #[test]
    fn keys_choose_methods_keeping_brightness() {
        let m = Method::parse(&["interpolateColor", "2"]).unwrap();
        assert_eq!(
            method_command(&method_for_key(1, &m).unwrap()),
            "method exact linear 0 2"
        );
        assert_eq!(
            method_command(&method_for_key(2, &m).unwrap()),
            "method interpolateCoeff linear 2"
        );
        assert_eq!(
            method_command(&method_for_key(4, &m).unwrap()),
            "method test 0.5"
        );
        assert_eq!(method_for_key(5, &m), None);
        assert_eq!(brightness(&scale_brightness(&m, 1.25)), 2.5);
    }
}
