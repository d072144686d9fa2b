//! VoRANG's own image codecs: one module per file format, each naming the specification it
//! follows and the choices it makes. The `image` crate covers the common formats; these are the
//! ones it does not write (most of them from the thesis's SDSC list, appendix A.2), written by
//! hand because each is a few dozen lines and no maintained crate writes them.
//!
//! Every reader here takes untrusted bytes: reads are bounds-checked ([`Bytes`]), image sizes
//! are checked against what the file can hold before anything is allocated ([`pixels`]), and
//! every failure is a message naming the byte offset (or line) and what was expected there.

pub mod avs;
pub mod ilbm;
pub mod packbits;
pub mod pbm;
pub mod pcx;
pub mod pfm;
pub mod pict;
pub mod postscript;
pub mod sgi;
pub mod sun_raster;
pub mod utah_rle;
pub mod viff;
pub mod xbm;
pub mod xwd;

use super::Framebuffer;

/// A decoded image: `width × height` RGB values in [0, 1] (8-bit values / 255; float formats as
/// stored), row-major from the top-left pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoded {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[f32; 3]>,
}

/// A reader: the file's bytes to its pixels, or what was wrong (without the file name).
pub type Reader = fn(&[u8]) -> Result<Decoded, String>;

/// A bounds-checked big/little-endian cursor over a file's bytes.
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes { data, pos: 0 }
    }

    pub fn at(data: &'a [u8], pos: usize) -> Self {
        Bytes { data, pos }
    }

    pub fn pos(&self) -> usize {
        self.pos
    }

    pub fn remaining(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    /// The next `n` bytes, or "byte P: expected WHAT (file ends after B bytes)".
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        match self.pos.checked_add(n) {
            Some(end) if end <= self.data.len() => {
                let s = &self.data[self.pos..end];
                self.pos = end;
                Ok(s)
            }
            _ => Err(format!(
                "byte {}: expected {what} ({n} bytes), but the file ends after {} bytes",
                self.pos,
                self.data.len()
            )),
        }
    }

    pub fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.take(1, what)?[0])
    }

    pub fn u16_be(&mut self, what: &str) -> Result<u16, String> {
        let b = self.take(2, what)?;
        Ok(u16::from_be_bytes([b[0], b[1]]))
    }

    pub fn u16_le(&mut self, what: &str) -> Result<u16, String> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    pub fn u32_be(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub fn u32_le(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
}

/// "byte P: WHAT" — an error at a byte offset.
pub fn at(pos: usize, what: impl std::fmt::Display) -> String {
    format!("byte {pos}: {what}")
}

/// A black `width × height` pixel buffer for `data_len` bytes of pixel data that hold at most
/// `per_byte.0 / per_byte.1` pixels per byte (the format's densest coding: 1/3 for plain 8-bit
/// RGB, more for run lengths): a header claiming more pixels than the data can hold is refused
/// before anything is allocated, so a small damaged file never asks for gigabytes.
pub fn pixels(
    width: usize,
    height: usize,
    data_len: usize,
    per_byte: (usize, usize),
) -> Result<Vec<[f32; 3]>, String> {
    if width == 0 || height == 0 {
        return Err(format!(
            "the header gives an empty image ({width} × {height} pixels)"
        ));
    }
    let n = width.saturating_mul(height);
    if n > data_len.saturating_mul(per_byte.0) / per_byte.1.max(1) {
        return Err(format!(
            "the header gives {width} × {height} pixels, more than {data_len} bytes of data can hold"
        ));
    }
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| format!("not enough memory for {width} × {height} pixels"))?;
    v.resize(n, [0.0; 3]);
    Ok(v)
}

/// An 8-bit value as an intensity in [0, 1].
#[inline]
pub fn unit(v: u8) -> f32 {
    f32::from(v) / 255.0
}

/// The 8-bit RGB a format without alpha stores for pixel `p`: the framebuffer's composited
/// colour, clipped and rounded.
#[inline]
pub fn rgb8(p: &[f32; 4]) -> [u8; 3] {
    [super::to_u8(p[0]), super::to_u8(p[1]), super::to_u8(p[2])]
}

/// Whether a 1-bit format stores pixel `p` as white: **luminance ≥ 0.5**, with the Rec. 601
/// weights of the `pgm` output on the clipped channels (NaN counts as black). A plain threshold
/// rather than dithering: the picture stays the one a reader of the thesis expects, and every
/// pixel is predictable for tests.
#[inline]
pub fn is_white(p: &[f32; 4]) -> bool {
    super::luma(p) >= 0.5
}

/// The rows of `fb`, top to bottom, as 8-bit RGB.
pub fn rows8(fb: &Framebuffer) -> impl Iterator<Item = Vec<[u8; 3]>> + '_ {
    fb.pixels
        .chunks(fb.width.max(1))
        .map(|r| r.iter().map(rgb8).collect())
}

/// Refuses a size above `max` in either direction (a format's header field width).
pub fn check_dims(fb: &Framebuffer, max: usize, format: &str) -> std::io::Result<()> {
    if fb.width == 0 || fb.height == 0 || fb.width > max || fb.height > max {
        return Err(std::io::Error::other(format!(
            "{format} images are at most {max} × {max} pixels (this one is {} × {})",
            fb.width, fb.height
        )));
    }
    Ok(())
}
