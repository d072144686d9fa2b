//! The session as script commands (the viewer's `p`): the commands that set the image size,
//! method, grid lines and view. Numbers are written in shortest round-trip form (Rust's
//! `Display` for `f64`), which Tcl reads back exactly, so the commands build the very same `View`
//! and `Method` and render the saved image bit for bit.

use super::Session;
use crate::render::Method;
use crate::render::lines::LineDraw;
use crate::scene::{Camera, TransformOp, View};

/// The script command that sets `method` (numbers in shortest round-trip form, so the command
/// gives back the same method bit for bit).
pub fn method_command(method: &Method) -> String {
    match method {
        Method::Exact(m) => format!("method exact {} {} {}", m.rule.name, m.step, m.brightness),
        Method::InterpolateCoeff(m) => {
            format!("method interpolateCoeff {} {}", m.rule.name, m.brightness)
        }
        Method::InterpolateColor(m) => format!("method interpolateColor {}", m.brightness),
        Method::Test(m) => format!("method test {}", m.opacity),
    }
}

/// The script commands that set the image size, method, grid lines and `view` (what `p`
/// prints). Numbers are in shortest round-trip form: the commands build the same view.
pub fn commands_for(
    view: &View,
    method: &Method,
    lines: &LineDraw,
    (width, height): (usize, usize),
) -> Vec<String> {
    let mut out = vec![
        format!("imagesize {width} {height}"),
        method_command(method),
    ];
    out.push(match lines {
        LineDraw::Off => "linedraw off".into(),
        LineDraw::All => "linedraw on".into(),
        LineDraw::Cells { field, values } => format!(
            "linedraw {field} {{{}}}",
            values
                .iter()
                .map(f64::to_string)
                .collect::<Vec<_>>()
                .join(" ")
        ),
    });
    let n = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(" ");
    for op in &view.transforms {
        out.push(match op {
            TransformOp::Scale(s) => format!("vol_scale {}", n(s)),
            TransformOp::Translate(t) => format!("vol_translate {}", n(t)),
            TransformOp::Rotate { axis, degrees } => {
                format!("vol_rotate {} {degrees}", n(axis))
            }
        });
    }
    let l = view.look_at;
    out.push(format!(
        "look_at {} {} {}",
        n(&l.eye),
        n(&l.reference),
        n(&l.up)
    ));
    match view.camera {
        Some(Camera::Ortho {
            left,
            right,
            bottom,
            top,
            front,
            back,
        }) => out.push(format!(
            "ortho_camera {}",
            n(&[left, right, bottom, top, front, back])
        )),
        Some(Camera::Persp {
            fovy,
            aspect,
            near,
            far,
        }) => out.push(format!("persp_camera {}", n(&[fovy, aspect, near, far]))),
        None => {}
    }
    out
}

impl Session {
    /// The commands that rebuild this session's image size, method, grid lines and view (after
    /// loading the volume and maps): rendering after them gives the same image bit for bit.
    pub fn script(&self) -> Vec<String> {
        commands_for(
            &self.view,
            &self.settings.method,
            &self.settings.lines,
            (self.settings.width, self.settings.height),
        )
    }
}
