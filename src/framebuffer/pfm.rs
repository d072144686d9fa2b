//! Portable float map (`PF`): RGB float32, little-endian (negative scale), rows from the bottom
//! of the image to the top, as the PFM specification says.

use std::io::{self, Write};

use super::Framebuffer;

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

/// Reads a PFM file written by [`write`] (for tests): width, height and RGB rows top to bottom.
pub fn read(bytes: &[u8]) -> Option<(usize, usize, Vec<[f32; 3]>)> {
    let text_end = bytes
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .nth(2)?
        .0
        + 1;
    let header = std::str::from_utf8(&bytes[..text_end]).ok()?;
    let mut words = header.split_whitespace();
    if words.next()? != "PF" {
        return None;
    }
    let w: usize = words.next()?.parse().ok()?;
    let h: usize = words.next()?.parse().ok()?;
    let scale: f32 = words.next()?.parse().ok()?;
    let data = &bytes[text_end..];
    if data.len() != w * h * 12 {
        return None;
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
    let mut out = vec![[0.0; 3]; w * h];
    for y in 0..h {
        for x in 0..w {
            let i = ((h - 1 - y) * w + x) * 3;
            out[y * w + x] = [get(i), get(i + 1), get(i + 2)];
        }
    }
    Some((w, h, out))
}
