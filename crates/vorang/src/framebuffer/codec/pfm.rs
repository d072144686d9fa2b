//! Portable float map (`PF`): RGB float32, little-endian (negative scale), rows from the bottom
//! of the image to the top, as the PFM specification says.

use std::io::{self, Write};

use super::{Decoded, at, pixels};
use crate::framebuffer::Framebuffer;

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    write!(w, "PF\n{} {}\n-1.0\n", fb.width, fb.height)?;
    let mut row = Vec::with_capacity(fb.width * 12);
    for y in (0..fb.height).rev() {
        row.clear();
        for p in &fb.pixels[y * fb.width..(y + 1) * fb.width] {
            for c in &p[..3] {
                row.extend_from_slice(&c.to_le_bytes());
            }
        }
        w.write_all(&row)?;
    }
    Ok(())
}

/// Reads a portable float map, colour (`PF`) or grey (`Pf`), in either byte order (the sign of
/// the scale): width, height and RGB rows from the top.
pub fn read(bytes: &[u8]) -> Result<(usize, usize, Vec<[f32; 3]>), String> {
    // Three whitespace-separated header words after the type, then one whitespace byte.
    let mut pos = 0;
    let mut words = Vec::new();
    while words.len() < 4 {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos || pos >= bytes.len() {
            return Err(at(pos, "expected the header `PF`, width, height and scale"));
        }
        words.push((
            start,
            String::from_utf8_lossy(&bytes[start..pos]).into_owned(),
        ));
    }
    let data = &bytes[pos + 1..];
    let channels = match words[0].1.as_str() {
        "PF" => 3,
        "Pf" => 1,
        w => return Err(at(0, format!("expected `PF` or `Pf`, found `{w}`"))),
    };
    let number = |i: usize, what: &str| -> Result<f64, String> {
        words[i]
            .1
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                at(
                    words[i].0,
                    format!("expected {what}, found `{}`", words[i].1),
                )
            })
    };
    let side = |i: usize, what: &str| -> Result<usize, String> {
        let v = number(i, what)?;
        if v >= 1.0 && v.fract() == 0.0 && v <= u32::MAX as f64 {
            Ok(v as usize)
        } else {
            Err(at(
                words[i].0,
                format!(
                    "expected {what} (a whole number ≥ 1), found `{}`",
                    words[i].1
                ),
            ))
        }
    };
    let w = side(1, "the width")?;
    let h = side(2, "the height")?;
    let scale = number(3, "the scale (negative: little-endian)")?;
    let mut out = pixels(w, h, data.len(), (1, 4 * channels))?;
    if data.len() != w * h * 4 * channels {
        return Err(at(
            pos + 1,
            format!(
                "expected {} bytes of pixels for {w} × {h} × {channels} floats, found {}",
                w * h * 4 * channels,
                data.len()
            ),
        ));
    }
    let get = |i: usize| {
        let b = [
            data[4 * i],
            data[4 * i + 1],
            data[4 * i + 2],
            data[4 * i + 3],
        ];
        if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    for y in 0..h {
        for x in 0..w {
            let i = ((h - 1 - y) * w + x) * channels;
            out[y * w + x] = if channels == 3 {
                [get(i), get(i + 1), get(i + 2)]
            } else {
                [get(i); 3]
            };
        }
    }
    Ok((w, h, out))
}

/// [`read`] as a [`Decoded`] image.
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let (width, height, rgb) = read(bytes)?;
    Ok(Decoded { width, height, rgb })
}
