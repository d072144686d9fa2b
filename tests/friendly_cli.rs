//! The friendlier program (in part): `vorang -e 'help …'` and a piped
//! `help …` print the help; an unknown command names the nearest known one.

use std::io::Write;
use std::process::{Command, Stdio};

use vorang_tcl::script::{Collect, Runner};

fn vorang() -> Command {
    Command::new(env!("CARGO_BIN_EXE_vorang"))
}

#[test]
fn help_prints_from_e_and_from_a_pipe() {
    let out = vorang().args(["-e", "help method"]).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("method name") && text.contains("interpolateColor"),
        "{text}"
    );

    let mut child = vorang()
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"help method\n")
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), text);

    // Other results stay quiet, as before.
    let out = vorang()
        .args(["-e", "set x [help]; set y 2"])
        .output()
        .unwrap();
    assert!(out.status.success() && out.stdout.is_empty());
}

#[test]
fn unknown_commands_suggest_the_nearest() {
    let mut r = Runner::new(Box::new(Collect::default()));
    for (typo, meant) in [
        ("rendr_btf", "render_btf"),
        ("colourmap x", "colormap"),
        ("vol_rotat 0 1 0 5", "vol_rotate"),
        ("forech x {1} {}", "foreach"),
    ] {
        let e = r.run_string(typo, "-e").unwrap_err();
        assert!(
            e.message.ends_with(&format!("did you mean \"{meant}\"?")),
            "{typo}: {e}"
        );
        assert_eq!(e.line, 1);
    }
    let e = r.run_string("qqqqqqqq", "-e").unwrap_err();
    assert_eq!(e.message, "invalid command name \"qqqqqqqq\"");
    // Procedures defined later are known too, and Tcl's own unknown handling still works.
    r.run_string("proc spin_volume {} { return ok }", "-e")
        .unwrap();
    let e = r.run_string("spin_volum", "-e").unwrap_err();
    assert!(e.message.contains("\"spin_volume\""), "{e}");
    assert_eq!(r.run_string("spin_volume", "-e").unwrap(), "ok");
}

#[test]
fn a_new_output_name_starts_at_one() {
    let dir = tempfile::tempdir().unwrap();
    let mut r = Runner::new(Box::new(Collect::default()));
    let d = dir.path().display();
    let script = format!(
        "volume {{{mesh}}}; imagesize 8 8
         output {{{d}/a.png}}; render_btf; render_btf
         output {{{d}/b.png}}; render_btf
         output {{{d}/b.png}}; render_btf
         output {{{d}/b.tiff}}; render_btf
         output {{{d}/c.png}}; set_nr 7; render_btf",
        mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/propEA/propEA.hmesh"),
    );
    r.run_string(&script, "-e").unwrap();
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "a.0001.png",
            "a.0002.png",
            "b.0001.png",
            "b.0002.png",
            "b.0003.tiff",
            "c.0007.png"
        ]
    );
}

/// A failing `-e` command is reported once: `-e:1: message`, without a trace that repeats it;
/// a failure inside a procedure still shows the calls that led there.
#[test]
fn e_errors_are_not_printed_twice() {
    let run = |script: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
            .args(["-e", script])
            .output()
            .unwrap();
        assert!(!out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let plain = run("no_such_command 1");
    assert_eq!(plain.matches("invalid command name").count(), 1, "{plain}");
    assert!(!plain.contains("Tcl trace"), "{plain}");
    let nested = run("proc f {} { vol_rotate 1 2 3 x }; f");
    assert_eq!(nested.matches("expected a number").count(), 1, "{nested}");
    assert!(nested.contains("(procedure \"f\" line 1)"), "{nested}");
}
