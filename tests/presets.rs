//! `colormap preset NAME lo hi` and `alphamap ramp lo hi chi_max`: the
//! published tables at their knots, the ramp, the messages, and a first picture without map
//! files.

use vorang::mapping::{PRESETS, ScalarAlpha, ScalarColor, preset_colormap, ramp_alphamap};
use vorang_tcl::script::{Collect, Runner};

fn color_at(name: &str, lo: f64, hi: f64, v: f64) -> [f64; 3] {
    let map = preset_colormap(name, lo, hi, None).unwrap();
    assert_eq!(map.lines.len(), 1);
    assert_eq!(map.lines[0].name, "SIMPLE_EMITTER");
    match map.lines[0].method.scalar_form() {
        Some(ScalarColor::Table(t)) => t.eval(v),
        other => panic!("not a table: {other:?}"),
    }
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn viridis_and_magma_follow_the_published_tables() {
    // matplotlib's viridis: entries 0, 255, and 135 (knot 9 of 0, 15, …, 255).
    assert_eq!(
        color_at("viridis", 2.0, 4.0, 2.0),
        [0.267004, 0.004874, 0.329415]
    );
    assert_eq!(
        color_at("viridis", 2.0, 4.0, 4.0),
        [0.993248, 0.906157, 0.143936]
    );
    let knot9 = 2.0 + 2.0 * 9.0 / 17.0;
    assert!(close(
        color_at("viridis", 2.0, 4.0, knot9),
        [0.121148, 0.592739, 0.544641],
        1e-12
    ));
    // The middle lies between entries 127 and 128 of the 256-entry list; the knots are 15
    // entries apart, so linear interpolation stays within a few 8-bit steps of them.
    let mid = color_at("viridis", 2.0, 4.0, 3.0);
    assert!(
        close(mid, [0.128729, 0.563265, 0.551229], 3.0 / 255.0),
        "{mid:?}"
    );
    // Clamped outside the range.
    assert_eq!(
        color_at("viridis", 2.0, 4.0, -10.0),
        color_at("viridis", 2.0, 4.0, 2.0)
    );
    assert_eq!(
        color_at("magma", 0.0, 1.0, 0.0),
        [0.001462, 0.000466, 0.013866]
    );
    assert_eq!(
        color_at("magma", 0.0, 1.0, 1.0),
        [0.987053, 0.991438, 0.749504]
    );
    assert_eq!(color_at("grey", -1.0, 1.0, 0.0), [0.5; 3]);
    assert_eq!(color_at("grey", -1.0, 1.0, 1.0), [1.0; 3]);
    // Every preset is a valid map over a small range far from zero.
    for p in PRESETS {
        assert!(preset_colormap(p.name, 1e6, 1e6 + 1.0, Some("temperature")).is_ok());
    }
}

#[test]
fn the_ramp_is_linear_from_zero_to_chi_max() {
    let map = ramp_alphamap(10.0, 20.0, 6.0, Some("2")).unwrap();
    assert_eq!(map.lines[0].name, "SIMPLE_ABSORBER");
    assert_eq!(map.data_field.field, vorang::mapping::FieldRef::Number(2));
    let Some(ScalarAlpha::Table(t)) = map.lines[0].method.scalar_form() else {
        panic!("not a table");
    };
    for (v, chi) in [
        (0.0, 0.0),
        (10.0, 0.0),
        (12.5, 1.5),
        (15.0, 3.0),
        (20.0, 6.0),
        (99.0, 6.0),
    ] {
        assert_eq!(t.eval(v), [chi], "at {v}");
    }
    assert!(ramp_alphamap(1.0, 1.0, 1.0, None).is_err());
    assert!(ramp_alphamap(0.0, 1.0, -1.0, None).is_err());
}

fn runner() -> Runner {
    Runner::new(Box::new(Collect::default()))
}

#[test]
fn wrong_presets_and_ranges_are_clear_errors() {
    let mut r = runner();
    let e = r
        .run_string("colormap preset rainbow 0 1", "-e")
        .unwrap_err();
    assert!(
        e.message.contains("unknown colour preset 'rainbow'")
            && e.message.contains("viridis, magma"),
        "{e}"
    );
    let e = r
        .run_string("colormap preset viridis 1 0", "-e")
        .unwrap_err();
    assert!(e.message.contains("lo < hi"), "{e}");
    let e = r.run_string("alphamap ramp 0 1", "-e").unwrap_err();
    assert!(e.message.contains("wrong # args"), "{e}");
    let e = r
        .run_string("colormap preset viridis a 1", "-e")
        .unwrap_err();
    assert!(e.message.contains("\"lo\""), "{e}");
    let help = r.run_string("help colormap", "-e").unwrap();
    assert!(
        help.contains("preset") && help.contains("coolwarm"),
        "{help}"
    );
}

#[test]
fn a_first_picture_needs_no_map_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("first.png");
    let mut r = runner();
    let script = format!(
        "imagesize 40 40; output {{{}}}; volume {{{}}}; linedraw off; background 0 0 0
         colormap preset viridis 0 1; alphamap ramp 0 1 2; method interpolateColor 2; render_btf",
        out.display(),
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/propEA/propEA.hmesh")
    );
    r.run_string(&script, "-e").unwrap();
    let img = image::open(dir.path().join("first.0001.png"))
        .unwrap()
        .to_rgb8();
    let lit = img.pixels().filter(|p| p.0 != [0, 0, 0]).count();
    assert!(lit > 100, "only {lit} pixels lit");
    // A field name works as the field argument, and a missing field is reported at the
    // command.
    r.run_string(
        "colormap preset magma 0 1 s; alphamap ramp 0 1 2 \"s\"",
        "-e",
    )
    .unwrap();
    let e = r
        .run_string("colormap preset magma 0 1 7", "-e")
        .unwrap_err();
    assert!(e.message.contains('7'), "{e}");
}

#[test]
fn info_suggests_a_first_picture() {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/propEA/propEA.hmesh"
    ));
    let (vol, _) = vorang::Volume::load(path).unwrap();
    let text = vorang::info::describe_volume(&vol, "ASCII 0.7");
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("try"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        line.contains("colormap preset viridis 0 1 0; alphamap ramp 0 1 "),
        "{line}"
    );
    // The suggestion runs as it is.
    let mut r = runner();
    r.run_string(&format!("volume {{{}}}", path.display()), "-e")
        .unwrap();
    r.run_string(line.trim_start().trim_start_matches("try").trim(), "-e")
        .unwrap();
}
