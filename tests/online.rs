//! `render_btf online` / `render_ftb online`: a window titled VoRANG
//! shows the image 1:1 — a screenshot of it equals the written 8-bit file — is reused by the
//! next online render, and without a display there is one warning and the file.

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

/// The farbraum scene turned so that every pixel differs from its neighbours.
fn scene() -> String {
    format!(
        "volume {{{}}}\ncolormap {{{}}}\nalphamap {{{}}}\nmethod interpolateColor 1\nvol_rotate 1 1 0 30\n",
        example("farbraum/farbraum.hmesh"),
        example("farbraum/identity.cmap"),
        example("farbraum/half.amap")
    )
}

#[test]
fn the_online_window_shows_the_written_pixels_and_is_reused() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tempfile::tempdir().unwrap();
    let script = format!(
        "{}output shot.png
imagesize 200 150
view_all
after 0 {{set ticked 1}}
render_btf online
puts \"events during the render: [info exists ticked]\"
update
exec xwd -silent -id [winfo id .vorang] -out first.xwd
puts \"title [wm title .vorang] windows [winfo children .]\"
set id [winfo id .vorang]
imagesize 120 90
vol_rotate 0 1 0 20
render_ftb online
update
exec xwd -silent -id [winfo id .vorang] -out second.xwd
puts \"same [expr {{$id eq [winfo id .vorang]}}] windows [winfo children .]\"
",
        scene()
    );
    std::fs::write(dir.path().join("online.tcl"), script).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("online.tcl")
        .current_dir(dir.path())
        .env("DISPLAY", &x.display)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.is_empty(), "no warnings with a display: {stderr}");
    assert!(stdout.contains("title VoRANG windows .vorang"), "{stdout}");
    assert!(stdout.contains("same 1 windows .vorang"), "{stdout}");
    // Tk's event loop ran during the render: the script's timer fired before `update`.
    assert!(stdout.contains("events during the render: 1"), "{stdout}");
    for (shot, file) in [
        ("first.xwd", "shot.0001.png"),
        ("second.xwd", "shot.0002.png"),
    ] {
        let shot = Shot::read(&dir.path().join(shot));
        let (w, h, rgb) = image_rgb(&dir.path().join(file));
        assert_eq!(
            (shot.width, shot.height),
            (w, h),
            "the window is the image's size"
        );
        let differ = shot.rgb.iter().zip(&rgb).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{file}: {differ} pixels differ on the screen");
        // Not a blank picture: the scene covers most of the window in many colours.
        let mut colours = rgb.clone();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 100, "{} colours", colours.len());
    }
}

#[test]
fn without_a_display_online_warns_once_and_writes_the_files() {
    let dir = tempfile::tempdir().unwrap();
    let script = format!(
        "{}output out.png\nimagesize 40 30\nview_all\nrender_btf online\nrender_ftb online\n",
        scene()
    );
    std::fs::write(dir.path().join("nodisplay.tcl"), script).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("nodisplay.tcl")
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].starts_with("render_btf: no window for 'online'"),
        "{stderr}"
    );
    assert!(
        warnings[0].contains("written to their files only"),
        "{stderr}"
    );
    for f in ["out.0001.png", "out.0002.png"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
}

/// What the window is fed while a render runs: every tile once, and together they are the
/// framebuffer.
#[test]
fn the_tiles_handed_out_during_a_render_make_up_the_image() {
    use std::sync::Mutex;
    use std::sync::atomic::AtomicBool;
    use vorang::mapping::{AlphaMap, ColorMap, Mapping};
    use vorang::render::{Method, Settings, Watch, render_watched};
    use vorang::scene::View;

    let vol = vorang::volume::jittered_box(3000, 0.1, 1);
    let (m, _) = Mapping::new(&ColorMap::default_map(), &AlphaMap::default_map(), &vol).unwrap();
    let settings = Settings {
        width: 150,
        height: 100,
        tile: 32,
        method: Method::parse(&["interpolateColor", "1"]).unwrap(),
        ..Settings::default()
    };
    let seen = Mutex::new((vec![[f32::NAN; 4]; 150 * 100], 0));
    let sink = |r: vorang::render::Rect, px: &[[f32; 4]]| {
        let mut s = seen.lock().unwrap();
        let w = r.x1 - r.x0;
        for (row, chunk) in px.chunks(w).enumerate() {
            let at = (r.y0 + row) * 150 + r.x0;
            s.0[at..at + w].copy_from_slice(chunk);
        }
        s.1 += 1;
    };
    let cancel = AtomicBool::new(false);
    let watch = Watch {
        progress: None,
        tile: Some(&sink),
        cancel: &cancel,
    };
    let (fb, _) = render_watched(&vol, &m, &View::default(), &settings, &watch).unwrap();
    let (pixels, tiles) = seen.into_inner().unwrap();
    assert_eq!(tiles, 5 * 4);
    assert!(pixels.iter().zip(&fb.pixels).all(|(a, b)| a == b));
}

/// A window that cannot be opened costs only the picture on the screen: with Tk's main window
/// destroyed by the script, `online` warns and writes the file.
#[test]
fn online_without_tk_main_window_warns_and_writes_the_file() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tempfile::tempdir().unwrap();
    let script = format!(
        "{}output out.png\nimagesize 40 30\nview_all\nrender_btf online\ndestroy .\nrender_btf online\nputs done\n",
        scene()
    );
    std::fs::write(dir.path().join("destroyed.tcl"), script).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .arg("destroyed.tcl")
        .current_dir(dir.path())
        .env("DISPLAY", &x.display)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("done"), "{stdout}");
    assert!(
        stderr.contains("render_btf: the online window cannot be opened"),
        "{stderr}"
    );
    for f in ["out.0001.png", "out.0002.png"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
}
