//! Encoding a movie's frames: animated GIF (the `image` crate's GIF encoder) and APNG (the
//! `png` crate) natively, other containers through the `ffmpeg` program.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};

use crate::atomic::write_atomically;
use crate::error::Error;
use crate::framebuffer::Framebuffer;

/// Writes one frame as a quickly compressed 8-bit RGBA PNG (what image files hold: opaque, or
/// straight alpha after `background none`).
pub fn write_frame(fb: &Framebuffer, file: &Path) -> Result<(), Error> {
    let rgba = fb.to_rgba8().map_err(Error::Invalid)?;
    let out = std::fs::File::create(file).map_err(|e| Error::io(file, e))?;
    let mut enc = png::Encoder::new(
        std::io::BufWriter::new(out),
        fb.width as u32,
        fb.height as u32,
    );
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let fail = |e: png::EncodingError| Error::Invalid(format!("{}: {e}", file.display()));
    let mut w = enc.write_header().map_err(fail)?;
    w.write_image_data(&rgba).map_err(fail)?;
    w.finish().map_err(fail)
}

fn read_frame(file: &Path) -> Result<RgbaImage, Error> {
    image::open(file).map(|i| i.to_rgba8()).map_err(|e| {
        Error::Invalid(format!(
            "{}: cannot read a movie frame: {e}",
            file.display()
        ))
    })
}

/// The frame duration as a fraction of a second, in milliseconds (`fps` ≥ 0.01).
fn frame_ms(fps: f64) -> u32 {
    (1000.0 / fps).round().max(1.0) as u32
}

fn failed(path: &Path, e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("{}: {e}", path.display()))
}

/// An animated GIF that loops forever; each frame gets its own 256-colour palette.
pub fn gif(frames: &[PathBuf], fps: f64, path: &Path) -> Result<(), Error> {
    write_atomically(path, |w| {
        // Speed 10 of 1…30: NeuQuant on a sample of the pixels, good enough for renders.
        let mut enc = GifEncoder::new_with_speed(w, 10);
        enc.set_repeat(Repeat::Infinite)
            .map_err(|e| failed(path, e))?;
        for f in frames {
            let img = read_frame(f).map_err(std::io::Error::other)?;
            let delay = Delay::from_numer_denom_ms(frame_ms(fps), 1);
            enc.encode_frame(Frame::from_parts(img, 0, 0, delay))
                .map_err(|e| failed(path, e))?;
        }
        Ok(())
    })
}

/// An animated PNG that loops forever, full colour with alpha.
pub fn apng(frames: &[PathBuf], fps: f64, path: &Path) -> Result<(), Error> {
    let first = read_frame(&frames[0])?;
    let (w, h) = first.dimensions();
    // The delay as a fraction: numerator/denominator seconds, both 16-bit.
    let ms = frame_ms(fps);
    let (num, den) = if ms <= u32::from(u16::MAX) {
        (ms as u16, 1000u16)
    } else {
        (((ms + 50) / 100).min(u32::from(u16::MAX)) as u16, 10u16)
    };
    write_atomically(path, |out| {
        let mut enc = png::Encoder::new(out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_animated(frames.len() as u32, 0)
            .map_err(|e| failed(path, e))?;
        enc.set_frame_delay(num, den).map_err(|e| failed(path, e))?;
        let mut writer = enc.write_header().map_err(|e| failed(path, e))?;
        for (i, f) in frames.iter().enumerate() {
            let img = if i == 0 {
                first.clone()
            } else {
                read_frame(f).map_err(std::io::Error::other)?
            };
            writer
                .write_image_data(img.as_raw())
                .map_err(|e| failed(path, e))?;
        }
        writer.finish().map_err(|e| failed(path, e))
    })
}

/// `program` in one of the folders of `path_var` (the `PATH` value), as an executable file.
pub fn find_program(program: &str, path_var: Option<&OsStr>) -> Option<PathBuf> {
    let names: Vec<String> = if cfg!(windows) {
        vec![format!("{program}.exe"), program.to_string()]
    } else {
        vec![program.to_string()]
    };
    std::env::split_paths(path_var?)
        .flat_map(|dir| names.iter().map(move |n| dir.join(n)))
        .find(|p| is_executable(p))
}

#[cfg(unix)]
fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    p.metadata()
        .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(p: &Path) -> bool {
    p.is_file()
}

/// What `movie x.mp4` says when there is no ffmpeg.
pub fn no_ffmpeg_message(path: &Path) -> String {
    format!(
        "{}: writing this format needs the ffmpeg program, which is not on the PATH: install it (apt-get install ffmpeg, brew install ffmpeg, or ffmpeg.org), or write an animated .gif or .apng, which VoRANG writes itself",
        path.display()
    )
}

/// Runs ffmpeg on the numbered frames (`pattern` with `%06d`): H.264/VP9 … as ffmpeg chooses
/// for the extension, yuv420p (what players expect), padded to even sizes.
pub fn ffmpeg(program: &Path, pattern: &Path, fps: f64, path: &Path) -> Result<(), Error> {
    let output = std::process::Command::new(program)
        .args(["-y", "-loglevel", "error", "-framerate"])
        .arg(format!("{fps}"))
        .arg("-i")
        .arg(pattern)
        .args([
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-pix_fmt",
            "yuv420p",
        ])
        .arg(path)
        .output()
        .map_err(|e| {
            Error::Invalid(format!(
                "{}: cannot run {}: {e}",
                path.display(),
                program.display()
            ))
        })?;
    if output.status.success() {
        Ok(())
    } else {
        Err(Error::Invalid(format!(
            "{}: ffmpeg failed ({}): {}",
            path.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn programs_are_found_only_on_the_path() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(find_program("ffmpeg", Some(dir.path().as_os_str())), None);
        assert_eq!(find_program("ffmpeg", None), None);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let fake = dir.path().join("ffmpeg");
            std::fs::write(&fake, "#!/bin/sh\n").unwrap();
            assert_eq!(find_program("ffmpeg", Some(dir.path().as_os_str())), None);
            std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
            assert_eq!(
                find_program("ffmpeg", Some(dir.path().as_os_str())),
                Some(fake)
            );
        }
    }

    #[test]
    fn frame_durations() {
        assert_eq!(frame_ms(10.0), 100);
        assert_eq!(frame_ms(24.0), 42);
        assert_eq!(frame_ms(1000.0), 1);
    }
}
