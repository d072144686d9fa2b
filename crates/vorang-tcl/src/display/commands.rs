//! What the viewer's `p` prints: the script commands that set the image size, method, grid lines
//! and view. Numbers are written in shortest round-trip form (Rust's `Display` for `f64`), which
//! Tcl reads back exactly, so the commands build the very same `View` and `Method` and render the
//! saved image bit for bit.

use vorang::render::Method;
use vorang::render::lines::LineDraw;
use vorang::scene::{Camera, TransformOp, View};

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
pub fn commands(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::display::controls::{BRIGHTNESS_STEP, scale_brightness};
    use crate::display::orbit::Orbit;

    fn unit_box() -> vorang::volume::Volume {
        vorang::volume::jittered_box(48, 0.0, 1)
    }

    #[test]
    fn printed_commands_build_the_same_view_and_method() {
        let vol = unit_box();
        let mut runner = crate::script::Runner::new(Box::new(crate::script::Collect::default()));
        let mut o = Orbit::new(&View::default(), &vol, 64, 48).unwrap();
        o.rotate(37.0, -11.0);
        o.zoom_by(1.1 * 1.1);
        o.pan(3.0, 7.0);
        let method = Method::parse(&["exact", "linear", "0", "1.3"]).unwrap();
        let method = scale_brightness(&method, BRIGHTNESS_STEP);
        let view = o.view();
        let script = commands(&view, &method, &LineDraw::Off, (64, 48)).join("\n");
        runner.session().volume = Some(std::sync::Arc::new(vol));
        runner.run_string(&script, "-e").unwrap();
        let s = runner.session();
        assert_eq!(s.view, view);
        assert_eq!(s.settings.method, method);
        assert_eq!((s.settings.width, s.settings.height), (64, 48));
        assert_eq!(s.settings.lines, LineDraw::Off);
    }
}
