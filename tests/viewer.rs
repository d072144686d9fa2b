//! The interactive viewer, driven by synthetic Tk events under Xvfb: a drag turns
//! the volume, the wheel zooms, shift-drag pans, `+` brightens; `p` prints commands and `s`
//! saves an image, and the printed commands render exactly the saved image.

mod common;

use std::path::Path;
use std::process::Command;

use common::screen::{Shot, Xvfb, image_rgb};

fn example(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(path)
        .display()
        .to_string()
}

fn scene() -> String {
    format!(
        "volume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\n",
        example("farbraum/farbraum.hmesh"),
        example("farbraum/identity.cmap"),
        example("farbraum/half.amap")
    )
}

/// Runs `script` (in `dir`) with the display `display` (none: `None`).
fn vorang(dir: &Path, script: &str, display: Option<&str>) -> std::process::Output {
    std::fs::write(dir.join("script.tcl"), script).unwrap();
    let mut c = Command::new(env!("CARGO_BIN_EXE_vorang"));
    c.arg("script.tcl").current_dir(dir);
    match display {
        Some(d) => c.env("DISPLAY", d),
        None => c.env_remove("DISPLAY"),
    };
    c.output().unwrap()
}

/// Waits (in Tcl, between the viewer's event rounds) until the viewer shows a refined frame.
const WHEN_REFINED: &str = r#"
proc when_refined {script} {
    if {[string match "*·  refined  ·*" $::vorang::view_status]} {
        uplevel #0 $script
    } else {
        after 50 [list when_refined $script]
    }
}
"#;

#[test]
fn the_viewer_turns_saves_and_prints_commands_that_render_the_saved_image() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tempfile::tempdir().unwrap();
    let script = format!(
        r#"{}{WHEN_REFINED}
imagesize 160 120
output saved.png
method interpolateCoeff constEA 1
set w .vorang_view.image
after 300 {{
    event generate $w <ButtonPress-1> -x 50 -y 50
    event generate $w <Motion> -x 80 -y 60 -state 256
    event generate $w <Motion> -x 95 -y 75 -state 256
    event generate $w <ButtonRelease-1> -x 95 -y 75
    event generate $w <Button-4> -x 80 -y 60
    event generate $w <ButtonPress-1> -x 10 -y 10 -state 1
    event generate $w <Motion> -x 16 -y 13 -state 257
    event generate $w <ButtonRelease-1> -x 16 -y 13
    event generate .vorang_view <KeyPress> -keysym plus
    after 50 {{when_refined {{
        # Let Tk redraw the label with the new photo (at idle time) and sync with the server.
        update
        exec xwd -silent -id [winfo id .vorang_view] -out viewer.xwd
        event generate .vorang_view <KeyPress> -keysym p
        event generate .vorang_view <KeyPress> -keysym s
        event generate .vorang_view <KeyPress> -keysym q
    }}}}
}}
# Never hang the test suite.
after 120000 {{event generate .vorang_view <KeyPress> -keysym q}}
view
puts "after view: [winfo exists .vorang_view]"
"#,
        scene()
    );
    let out = vorang(dir.path(), &script, Some(&x.display));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("after view: 0"), "{stdout}");
    let printed: Vec<&str> = stdout
        .lines()
        .skip_while(|l| !l.starts_with("# view:"))
        .skip(1)
        .take_while(|l| !l.contains("saved from the viewer"))
        .collect();
    let printed = printed.join("\n");
    assert!(
        printed.contains("method interpolateCoeff constEA 1.25"),
        "{printed}"
    );
    assert!(
        printed.contains("\nvol_rotate "),
        "the drag turned it: {printed}"
    );
    assert!(printed.contains("\northo_camera "), "{printed}");
    assert!(dir.path().join("saved.0001.png").is_file(), "{stdout}");

    let again = format!("{}output again.png\n{printed}\nrender_btf\n", scene());
    let out = vorang(dir.path(), &again, None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let saved = image::open(dir.path().join("saved.0001.png"))
        .unwrap()
        .to_rgba8();
    let rendered = image::open(dir.path().join("again.0001.png"))
        .unwrap()
        .to_rgba8();
    assert_eq!(saved.dimensions(), (160, 120));
    assert!(
        saved == rendered,
        "the printed commands render the saved image"
    );

    // The window showed the refined image 1:1 above its legend and status line.
    let shot = Shot::read(&dir.path().join("viewer.xwd"));
    let (w, h, rgb) = image_rgb(&dir.path().join("saved.0001.png"));
    assert!(shot.width >= w && shot.height > h);
    let differ = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| shot.rgb[y * shot.width + x] != rgb[y * w + x])
        .count();
    assert_eq!(differ, 0, "{differ} pixels differ on the screen");
}

#[test]
fn without_a_display_view_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = vorang(dir.path(), &format!("{}view\n", scene()), None);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("script.tcl:4: view: no window can be opened"),
        "{stderr}"
    );
}

#[test]
fn vorang_view_loads_the_scene_and_needs_a_display() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .args(["view", &example("farbraum/farbraum.hmesh"), "--colormap"])
        .arg(example("farbraum/identity.cmap"))
        .args(["--size", "64", "48", "--method", "exact linear 0 1"])
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with("vorang: view: no window can be opened"),
        "{stderr}"
    );
    // A bad option value is reported by the command it becomes.
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .args(["view", &example("farbraum/farbraum.hmesh")])
        .args(["--method", "splat 1"])
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("unknown method 'splat'"), "{stderr}");
    // Paths reach the script commands as they are, spaces and Tcl's special characters too.
    let odd = dir.path().join("a [b] {c} $d;e");
    std::fs::create_dir(&odd).unwrap();
    std::fs::copy(example("farbraum/farbraum.hmesh"), odd.join("f g.hmesh")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("view")
        .arg(odd.join("f g.hmesh"))
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no window can be opened"), "{stderr}");
}

/// `vorang view FILE` without maps shows the first picture `vorang info` suggests (viridis and
/// an absorption ramp over the first field's range) and says so — before it needs a window.
#[test]
fn view_without_maps_uses_the_preset_and_says_so() {
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .args(["view", &example("inclusion/inclusion.vtu")])
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stdout.contains("view: no maps given: the viridis preset and an absorption ramp")
            && stdout.contains("field 0 \"temperature\", [0, 0.715872]"),
        "{stdout}"
    );
    assert!(stderr.contains("no window can be opened"), "{stderr}");
    // With a colormap given, no preset.
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .args(["view", &example("inclusion/inclusion.vtu"), "--colormap"])
        .arg(example("inclusion/temperature.cmap"))
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert!(!String::from_utf8_lossy(&out.stdout).contains("preset"));
}
