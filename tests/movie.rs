//! `movie FILE ?fps?` … `movie close`: animated GIF and APNG written
//! natively and decoded back frame by frame; mp4 without ffmpeg is a clear error.

use std::io::BufReader;
use std::path::Path;

use image::AnimationDecoder;
use image::codecs::gif::GifDecoder;
use image::codecs::png::PngDecoder;
use vorang_tcl::script::{Collect, Runner};

const MESH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/propEA/propEA.hmesh");

/// Renders three turned frames into `movie` (a path in `dir`) and closes it.
fn three_frames(dir: &Path, movie: &str, close: bool) -> Runner {
    let mut r = Runner::new(Box::new(Collect::default()));
    let script = format!(
        "imagesize 48 32; output {{{out}}}; volume {{{MESH}}}; linedraw off; background 0 0 0
         colormap preset viridis 0 1; alphamap ramp 0 1 2; method interpolateColor 2
         movie {{{movie}}} 5
         for {{set i 0}} {{$i < 3}} {{incr i}} {{ vol_rotate 0 1 0 30; render_btf }}
         {close}",
        out = dir.join("still.png").display(),
        movie = dir.join(movie).display(),
        close = if close { "movie close" } else { "" },
    );
    r.run_string(&script, "-e").unwrap();
    r
}

fn frames_of(frames: image::Frames) -> Vec<image::Frame> {
    frames.collect_frames().unwrap()
}

/// Only the movie is left: no numbered images, no frame folder.
fn only(dir: &Path, name: &str) {
    let names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, [name.to_string()]);
}

#[test]
fn a_gif_has_its_frames() {
    let dir = tempfile::tempdir().unwrap();
    three_frames(dir.path(), "spin.gif", true);
    only(dir.path(), "spin.gif");
    let file = std::fs::File::open(dir.path().join("spin.gif")).unwrap();
    let frames = frames_of(GifDecoder::new(BufReader::new(file)).unwrap().into_frames());
    assert_eq!(frames.len(), 3);
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (48, 32));
        let (num, den) = f.delay().numer_denom_ms();
        assert_eq!(num / den, 200);
    }
    // The volume turns: the frames differ.
    assert_ne!(frames[0].buffer(), frames[1].buffer());
}

#[test]
fn an_apng_has_its_frames() {
    let dir = tempfile::tempdir().unwrap();
    three_frames(dir.path(), "spin.apng", true);
    only(dir.path(), "spin.apng");
    let file = std::fs::File::open(dir.path().join("spin.apng")).unwrap();
    let decoder = PngDecoder::new(BufReader::new(file)).unwrap();
    let frames = frames_of(decoder.apng().unwrap().into_frames());
    assert_eq!(frames.len(), 3);
    assert_ne!(frames[0].buffer(), frames[2].buffer());
    let lit = frames[0]
        .buffer()
        .pixels()
        .filter(|p| p.0[..3] != [0, 0, 0])
        .count();
    assert!(lit > 50, "{lit}");
}

#[test]
fn the_end_of_the_session_closes_the_movie() {
    let dir = tempfile::tempdir().unwrap();
    drop(three_frames(dir.path(), "open.gif", false));
    only(dir.path(), "open.gif");
}

#[test]
fn movie_errors_are_clear() {
    let dir = tempfile::tempdir().unwrap();
    let mut r = Runner::new(Box::new(Collect::default()));
    let e = r.run_string("movie close", "-e").unwrap_err();
    assert!(e.message.contains("no movie is open"), "{e}");
    let e = r
        .run_string(
            &format!("movie {{{}}}", dir.path().join("a.avi2").display()),
            "-e",
        )
        .unwrap_err();
    assert!(e.message.contains("unknown movie format"), "{e}");
    let script = format!(
        "volume {{{MESH}}}; imagesize 20 20; movie {{{}}}; render_btf; imagesize 30 20; render_btf",
        dir.path().join("sizes.gif").display()
    );
    let e = r.run_string(&script, "-e").unwrap_err();
    assert!(e.message.contains("one size"), "{e}");
    // A movie without frames writes nothing.
    let e = r
        .run_string(
            &format!(
                "movie {{{}}}; movie close",
                dir.path().join("empty.gif").display()
            ),
            "-e",
        )
        .unwrap_err();
    assert!(e.message.contains("no frames"), "{e}");
}

#[test]
fn mp4_without_ffmpeg_says_what_to_do() {
    let dir = tempfile::tempdir().unwrap();
    let empty = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vorang"))
        .env("PATH", empty.path())
        .arg("-e")
        .arg(format!(
            "movie {{{}}}",
            dir.path().join("spin.mp4").display()
        ))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("needs the ffmpeg program, which is not on the PATH")
            && err.contains(".gif or .apng"),
        "{err}"
    );
}

#[test]
fn mp4_through_ffmpeg_when_it_is_installed() {
    let on_path = std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("ffmpeg").is_file()));
    if !on_path {
        eprintln!("ffmpeg is not installed: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    three_frames(dir.path(), "spin.mp4", true);
    only(dir.path(), "spin.mp4");
    assert!(
        std::fs::metadata(dir.path().join("spin.mp4"))
            .unwrap()
            .len()
            > 100
    );
}
