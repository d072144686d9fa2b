//! The examples of `docs/guide.md` are real: its HyperMesh, colormap and alphamap blocks are
//! written to files and its Tcl block renders them, and its pictures are rendered from its own
//! map blocks by `docs/images/make.tcl` (run here small), so the guide cannot drift from the
//! program.

use std::collections::BTreeSet;
use std::path::PathBuf;

use vorang::mapping::{ALPHA_METHODS, COLOR_METHODS};
use vorang_tcl::script::{Collect, Runner};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn guide() -> String {
    std::fs::read_to_string(repo().join("docs/guide.md")).unwrap()
}

/// The guide's map blocks: (kind, file name, text).
fn map_blocks(guide: &str) -> Vec<(String, String, String)> {
    blocks(guide)
        .into_iter()
        .filter_map(|(info, body)| {
            let mut w = info.split_whitespace();
            match (w.next(), w.next()) {
                (Some(k @ ("colormap" | "alphamap")), Some(name)) => {
                    Some((k.to_string(), name.to_string(), body))
                }
                _ => None,
            }
        })
        .collect()
}

/// The fenced blocks of `text`: (info string, body).
fn blocks(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if let Some(info) = line.strip_prefix("```") {
            let mut body = String::new();
            for l in lines.by_ref() {
                if l.starts_with("```") {
                    break;
                }
                body.push_str(l);
                body.push('\n');
            }
            out.push((info.trim().to_string(), body));
        }
    }
    out
}

#[test]
fn the_guide_s_examples_load_and_render() {
    let guide = guide();
    let tmp = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    let mut script = None;
    for (info, body) in blocks(&guide) {
        let mut words = info.split_whitespace();
        match (words.next(), words.next()) {
            (Some("hypermesh" | "colormap" | "alphamap"), Some(name)) => {
                std::fs::write(tmp.path().join(name), body).unwrap();
                files.push(name.to_string());
            }
            // The first Tcl block is the example of these files; the time-series one has a
            // test of its own.
            (Some("tcl"), _) if script.is_none() => script = Some(body),
            _ => {}
        }
    }
    for name in ["one.hmesh", "t.cmap", "t.amap"] {
        assert!(
            files.iter().any(|f| f == name),
            "the guide's example file {name}"
        );
    }
    let script = script.expect("the guide's Tcl example");
    let path = tmp.path().join("guide.tcl");
    std::fs::write(&path, format!("imagesize 48 40\n{script}")).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    runner
        .run_file(&path)
        .unwrap_or_else(|e| panic!("{e}\n{}", e.trace));
    let written = runner.session().written().to_vec();
    assert_eq!(written.len(), 4, "{written:?}");
    for w in &written {
        let img = image::open(w).unwrap().to_rgb8();
        // Something was drawn: not every pixel is the white background.
        assert!(
            img.pixels().any(|p| p.0 != [255, 255, 255]),
            "{}",
            w.display()
        );
    }
}

/// The guide's time-series example runs on `tests/data/series/flow.pvd` and writes one movie
/// frame per step.
#[test]
fn the_guide_s_time_series_example_renders_every_step() {
    let body = blocks(&guide())
        .into_iter()
        .find(|(info, body)| info == "tcl" && body.contains("timestep"))
        .map(|(_, body)| body)
        .expect("the guide's time-series example");
    let flow = repo().join("tests/data/series/flow.pvd");
    assert!(body.contains("volume flow.pvd"), "{body}");
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("series.tcl");
    let script = body.replace("volume flow.pvd", &format!("volume {{{}}}", flow.display()));
    std::fs::write(&path, format!("imagesize 48 40\n{script}")).unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    runner
        .run_file(&path)
        .unwrap_or_else(|e| panic!("{e}\n{}", e.trace));
    let movie = tmp.path().join("flow.gif");
    let file = std::fs::File::open(&movie).unwrap();
    let frames = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(file))
        .map(|d| image::AnimationDecoder::into_frames(d).count())
        .unwrap();
    assert_eq!(frames, 3);
}

/// `docs/images/make.tcl` renders every picture of the guide from the guide's own map blocks:
/// run at an eighth of the size, it must cover every colour and alpha method, use every map
/// block of the guide that the Tcl example does not, list the same pictures as the committed
/// `docs/images/pictures.txt`, and each picture must be committed (small) and shown.
#[test]
fn the_guide_s_pictures_are_rendered_from_its_map_blocks() {
    let guide = guide();
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let wrapper = tmp.path().join("small.tcl");
    std::fs::write(
        &wrapper,
        format!(
            "set scale 0.125\nset outdir {{{}}}\nsource {{{}}}\n",
            tmp.path().display(),
            repo().join("docs/images/make.tcl").display()
        ),
    )
    .unwrap();
    let mut runner = Runner::new(Box::new(Collect::default()));
    runner
        .run_file(&wrapper)
        .unwrap_or_else(|e| panic!("{e}\n{}", e.trace));

    let listed = std::fs::read_to_string(tmp.path().join("pictures.txt")).unwrap();
    let committed = std::fs::read_to_string(repo().join("docs/images/pictures.txt")).unwrap();
    assert_eq!(
        listed.trim(),
        committed.trim(),
        "docs/images/pictures.txt is out of date: run docs/images/make.tcl"
    );

    let blocks = map_blocks(&guide);
    let script: String = self::blocks(&guide)
        .into_iter()
        .filter(|(info, _)| info == "tcl")
        .map(|(_, body)| body)
        .collect();
    let mut used = BTreeSet::new();
    for line in listed.lines() {
        let mut words = line.split_whitespace();
        let picture = words.next().unwrap();
        used.extend(words.map(str::to_string));
        // Rendered here, and not a blank image.
        let small = image::open(tmp.path().join(picture)).unwrap().to_rgb8();
        let first = small.get_pixel(0, 0).0;
        assert!(small.pixels().any(|p| p.0 != first), "{picture} is uniform");
        // Committed, small, and shown in the guide or the README.
        let path = repo().join("docs/images").join(picture);
        let bytes = std::fs::metadata(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .len();
        assert!(bytes < 150_000, "{picture}: {bytes} bytes");
        let (w, h) = image::image_dimensions(&path).unwrap();
        assert!(
            (192..=384).contains(&w) && (192..=384).contains(&h),
            "{picture}: {w}×{h}"
        );
        let shown = format!("images/{picture})");
        assert!(
            guide.contains(&shown) || readme.contains(&format!("docs/{shown}")),
            "{picture} is not shown in docs/guide.md or README.md"
        );
    }

    let mut methods = BTreeSet::new();
    for (kind, name, text) in &blocks {
        if !used.contains(name) {
            assert!(
                script.contains(name.as_str()),
                "the guide's {kind} {name} is neither pictured by docs/images/make.tcl nor used by its Tcl example"
            );
            continue;
        }
        // The method a pictured block shows: its first method line's first word.
        let method = text
            .lines()
            .skip(1)
            .map(str::trim)
            .find(|l| {
                !l.is_empty()
                    && !l.starts_with('#')
                    && !l.starts_with("DataField")
                    && !l.starts_with("CategoryField")
            })
            .and_then(|l| l.split_whitespace().next())
            .unwrap();
        methods.insert(format!("{kind} {method}"));
    }
    for m in COLOR_METHODS {
        assert!(
            methods.contains(&format!("colormap {}", m.name)),
            "colour method {} has no example with a picture in docs/guide.md ({methods:?})",
            m.name
        );
    }
    for m in ALPHA_METHODS {
        assert!(
            methods.contains(&format!("alphamap {}", m.name)),
            "alpha method {} has no example with a picture in docs/guide.md ({methods:?})",
            m.name
        );
    }
}
