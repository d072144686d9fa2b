//! `legend on|off ?position?`: the bar's pixels in the written image are the
//! colormap's colours at the values they stand for, at every position; `legend off` leaves
//! the image as it was.

use std::path::{Path, PathBuf};

use vorang::Volume;
use vorang::framebuffer::to_u8;
use vorang::legend::{ColorScale, Layout, Place};
use vorang::mapping::{ScalarColor, preset_colormap};
use vorang_tcl::script::{Collect, Runner};

const MESH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/propEA/propEA.hmesh");
const W: usize = 220;
const H: usize = 160;

/// Renders the propEA block with the magma preset over [-1, 3]; `legend` is the script's
/// legend command (or nothing). Returns the image file.
fn render(dir: &Path, name: &str, legend: &str) -> PathBuf {
    let mut r = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize {W} {H}; output {{{}}}; volume {{{MESH}}}; linedraw off; view_all
         colormap preset magma -1 3; alphamap ramp 0 1 1.5; method interpolateColor 1.5
         {legend}; render_btf",
        dir.join(format!("{name}.png")).display(),
    );
    r.run_string(&script, "-e").unwrap();
    dir.join(format!("{name}.0001.png"))
}

#[test]
fn the_bar_shows_the_colormap_at_its_values() {
    let dir = tempfile::tempdir().unwrap();
    let (vol, _) = Volume::load(Path::new(MESH)).unwrap();
    let map = preset_colormap("magma", -1.0, 3.0, None).unwrap();
    let Some(ScalarColor::Table(table)) = map.lines[0].method.scalar_form() else {
        panic!("not a table");
    };
    let scale = ColorScale::of_map(&map, &vol).unwrap();
    assert_eq!((scale.lo, scale.hi), (-1.0, 3.0));
    for (place, word) in [
        (Place::Right, "right"),
        (Place::Left, "left"),
        (Place::Top, "top"),
        (Place::Bottom, "bottom"),
    ] {
        let file = render(dir.path(), word, &format!("legend on {word}"));
        let img = image::open(&file).unwrap().to_rgba8();
        let layout = Layout::new(place, W, H, &scale).unwrap();
        assert!(layout.len() > 50, "{layout:?}");
        let labels: Vec<&str> = layout.labels.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(labels.first(), Some(&"-1"), "{labels:?}");
        assert_eq!(labels.last(), Some(&"3"), "{labels:?}");
        let mut checked = 0;
        for y in layout.y0..layout.y1 {
            for x in layout.x0..layout.x1 {
                let v = layout.value_at(x, y);
                assert!((-1.0..=3.0).contains(&v));
                let want = table.eval(v).map(|c| to_u8(c as f32));
                let got = img.get_pixel(x as u32, y as u32).0;
                assert_eq!(got[..3], want, "{word}: pixel {x},{y} for value {v}");
                assert_eq!(got[3], 255);
                checked += 1;
            }
        }
        assert!(checked > 300);
        // The low end is at the bottom or on the left.
        let low = if matches!(place, Place::Right | Place::Left) {
            layout.value_at(layout.x0, layout.y1 - 1)
        } else {
            layout.value_at(layout.x0, layout.y0)
        };
        assert!(low < -0.95, "{word}: {low}");
    }
}

#[test]
fn legend_off_leaves_the_image_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let plain = image::open(render(dir.path(), "plain", ""))
        .unwrap()
        .to_rgba8();
    let off = image::open(render(dir.path(), "off", "legend on top; legend off"))
        .unwrap()
        .to_rgba8();
    assert_eq!(plain, off);
    let on = image::open(render(dir.path(), "on", "legend on"))
        .unwrap()
        .to_rgba8();
    let changed = plain
        .pixels()
        .zip(on.pixels())
        .filter(|(a, b)| a != b)
        .count();
    // The bar, its frame and labels: a small part of the image.
    assert!(changed > 300 && changed < W * H / 4, "{changed}");
}

#[test]
fn wrong_positions_and_maps_without_a_scale_are_reported() {
    let mut r = Runner::new(Box::new(Collect::default()));
    let e = r.run_string("legend on middle", "-e").unwrap_err();
    assert!(e.message.contains("right, left, top, bottom"), "{e}");
    let e = r.run_string("legend maybe", "-e").unwrap_err();
    assert!(e.message.contains("on or off"), "{e}");
    let farbraum = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/farbraum");
    let (vol, _) = Volume::load(&Path::new(farbraum).join("farbraum.hmesh")).unwrap();
    let (identity, _) = vorang::mapping::read_map::<dyn vorang::mapping::ColorShading>(
        &Path::new(farbraum).join("identity.cmap"),
    )
    .unwrap();
    let e = ColorScale::of_map(&identity, &vol).unwrap_err();
    assert!(e.contains("IDENTITY"), "{e}");
    // CONSTANT (the default map) spans the field's data range.
    let constant = vorang::mapping::ColorMap::default_map();
    let (vol, _) = Volume::load(Path::new(MESH)).unwrap();
    let scale = ColorScale::of_map(&constant, &vol).unwrap();
    assert_eq!((scale.lo, scale.hi), (0.0, 1.0));
    assert_eq!(scale.color(0.5), [1.0, 0.0, 0.0]);
}

#[test]
fn a_lit_table_shows_its_colours_before_the_lights() {
    let (vol, _) = Volume::load(Path::new(MESH)).unwrap();
    let text = "# VoRANG Colormap 1.0\nLIT_EMITTER @1\n@1\n0.2 0.8 0.5 10\n0 0 1 -1\n1 0.5 0 3\n";
    let map = vorang::mapping::parse_map::<dyn vorang::mapping::ColorShading>(
        text.as_bytes(),
        "lit.cmap",
    )
    .unwrap()
    .0;
    let scale = ColorScale::of_map(&map, &vol).unwrap();
    assert_eq!((scale.lo, scale.hi), (-1.0, 3.0));
    let Some(ScalarColor::Table(table)) = map.lines[0].method.legend_form() else {
        panic!("no table");
    };
    assert_eq!(table.eval(1.0), [0.5, 0.25, 0.5]);
    // Not a scalar form: the renderer's one-table fast path must not skip the lights.
    assert!(map.lines[0].method.scalar_form().is_none());
}
