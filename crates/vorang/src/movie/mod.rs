//! Animations (`movie FILE ?fps?` … `movie close`): while a movie is open,
//! every render adds its frame (legend included) to it instead of writing a numbered image;
//! `movie close` writes the file.
//!
//! Frames are kept as PNG files in a hidden folder next to the movie (`.NAME.frames/`), not in
//! memory: a long animation of large images would not fit, APNG needs the frame count before
//! the first frame, and ffmpeg reads numbered files. Closing encodes them — animated GIF and
//! APNG natively, mp4/webm/mkv/mov by the `ffmpeg` program — and removes the folder.

mod encode;

use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::framebuffer::Framebuffer;

/// How a movie file is written, from its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MovieFormat {
    /// Animated GIF (256 colours per frame).
    Gif,
    /// Animated PNG (`.apng`, or `.png`): full colour and alpha.
    Apng,
    /// Through `ffmpeg` (`.mp4`, `.webm`, `.mkv`, `.mov`).
    Ffmpeg,
}

/// The extensions `movie` accepts, for help and messages.
pub const MOVIE_EXTENSIONS: &str =
    "gif, apng, png (APNG), mp4, webm, mkv, mov (the last four through ffmpeg)";

impl MovieFormat {
    pub fn for_path(path: &Path) -> Result<MovieFormat, Error> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        match ext.as_str() {
            "gif" => Ok(MovieFormat::Gif),
            "apng" | "png" => Ok(MovieFormat::Apng),
            "mp4" | "webm" | "mkv" | "mov" => Ok(MovieFormat::Ffmpeg),
            _ => Err(Error::Invalid(format!(
                "{}: unknown movie format '{ext}': expected one of {MOVIE_EXTENSIONS}",
                path.display()
            ))),
        }
    }
}

/// An open movie: where it goes, its frame rate and the frames so far.
#[derive(Debug)]
pub struct Movie {
    pub path: PathBuf,
    pub format: MovieFormat,
    pub fps: f64,
    frames_dir: PathBuf,
    frames: usize,
    size: Option<(usize, usize)>,
    /// The ffmpeg program, found when the movie is opened (so that a missing one is reported
    /// before any rendering).
    ffmpeg: Option<PathBuf>,
}

impl Movie {
    /// Opens a movie at `path` with `fps` frames per second; creates the frame folder (and the
    /// movie's missing parent folders). For ffmpeg formats the program must be on `PATH`.
    pub fn open(path: &Path, fps: f64) -> Result<Movie, Error> {
        let format = MovieFormat::for_path(path)?;
        if !(fps.is_finite() && (0.01..=1000.0).contains(&fps)) {
            return Err(Error::Invalid(format!(
                "frame rate {fps}: expected 0.01 … 1000 frames per second"
            )));
        }
        let ffmpeg = match format {
            MovieFormat::Ffmpeg => Some(
                encode::find_program("ffmpeg", std::env::var_os("PATH").as_deref())
                    .ok_or_else(|| Error::Invalid(encode::no_ffmpeg_message(path)))?,
            ),
            _ => None,
        };
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "movie".into());
        let frames_dir = path.with_file_name(format!(".{name}.frames"));
        if frames_dir.exists() {
            std::fs::remove_dir_all(&frames_dir).map_err(|e| Error::io(&frames_dir, e))?;
        }
        std::fs::create_dir_all(&frames_dir).map_err(|e| Error::io(&frames_dir, e))?;
        Ok(Movie {
            path: path.to_path_buf(),
            format,
            fps,
            frames_dir,
            frames: 0,
            size: None,
            ffmpeg,
        })
    }

    /// The number of frames added so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Adds a rendered image as the next frame (all frames must have the first one's size).
    pub fn add(&mut self, fb: &Framebuffer) -> Result<(), Error> {
        match self.size {
            Some((w, h)) if (w, h) != (fb.width, fb.height) => {
                return Err(Error::Invalid(format!(
                    "{}: the frames of a movie must have one size: this one is {}×{}, the first was {w}×{h}",
                    self.path.display(),
                    fb.width,
                    fb.height
                )));
            }
            _ => self.size = Some((fb.width, fb.height)),
        }
        let file = self.frame_path(self.frames);
        encode::write_frame(fb, &file)?;
        self.frames += 1;
        Ok(())
    }

    fn frame_path(&self, i: usize) -> PathBuf {
        self.frames_dir.join(format!("frame{:06}.png", i + 1))
    }

    /// Writes the movie and removes the frame folder. A movie without frames is an error (and
    /// writes nothing).
    pub fn finish(self) -> Result<PathBuf, Error> {
        let result = self.encode();
        let _ = std::fs::remove_dir_all(&self.frames_dir);
        result.map(|()| self.path.clone())
    }

    fn encode(&self) -> Result<(), Error> {
        if self.frames == 0 {
            return Err(Error::Invalid(format!(
                "{}: no frames: render while the movie is open",
                self.path.display()
            )));
        }
        let frames: Vec<PathBuf> = (0..self.frames).map(|i| self.frame_path(i)).collect();
        match self.format {
            MovieFormat::Gif => encode::gif(&frames, self.fps, &self.path),
            MovieFormat::Apng => encode::apng(&frames, self.fps, &self.path),
            MovieFormat::Ffmpeg => encode::ffmpeg(
                self.ffmpeg.as_deref().unwrap_or(Path::new("ffmpeg")),
                &self.frames_dir.join("frame%06d.png"),
                self.fps,
                &self.path,
            ),
        }
    }

    /// Drops the frames without writing the movie.
    pub fn discard(self) {
        let _ = std::fs::remove_dir_all(&self.frames_dir);
    }
}
