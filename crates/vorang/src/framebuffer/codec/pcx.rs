//! ZSoft PC Paintbrush (`.pcx`, ZSoft's "Technical Reference Manual", version 5 = Paintbrush
//! 3.0): a 128-byte little-endian header, then run-length coded scanlines. VoRANG writes 24-bit
//! colour as three 8-bit planes (R, G, B rows one after the other per scanline), each plane row
//! `bytes per line` long (even, as the manual requires) and coded on its own, so no run crosses
//! a plane. Coding: a byte with its two top bits set carries a count (its low six bits) for the
//! next byte; any other byte is itself. The reader takes 8-bit 3-plane (and 4-plane, alpha
//! ignored) colour, 8-bit 1-plane with the 256-colour palette at the end, and 1-bit 1-plane.

use std::io::{self, Write};

use super::{Bytes, Decoded, at, pixels, rows8, unit};
use crate::framebuffer::Framebuffer;

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    super::check_dims(fb, u16::MAX as usize, "PCX")?;
    let bytes_per_line = fb.width.next_multiple_of(2);
    let mut h = [0u8; 128];
    h[0] = 10; // ZSoft
    h[1] = 5; // version 5: Paintbrush 3.0 and later (24-bit)
    h[2] = 1; // run-length coding
    h[3] = 8; // bits per pixel and plane
    h[8..10].copy_from_slice(&(fb.width as u16 - 1).to_le_bytes()); // x max
    h[10..12].copy_from_slice(&(fb.height as u16 - 1).to_le_bytes()); // y max
    h[12..14].copy_from_slice(&72u16.to_le_bytes()); // dpi
    h[14..16].copy_from_slice(&72u16.to_le_bytes());
    h[65] = 3; // planes
    h[66..68].copy_from_slice(&(bytes_per_line as u16).to_le_bytes());
    h[68] = 1; // palette info: colour
    w.write_all(&h)?;
    let mut plane = vec![0u8; bytes_per_line];
    let mut out = Vec::new();
    for row in rows8(fb) {
        out.clear();
        for c in 0..3 {
            for (x, p) in row.iter().enumerate() {
                plane[x] = p[c];
            }
            encode(&plane, &mut out);
        }
        w.write_all(&out)?;
    }
    Ok(())
}

fn encode(plane: &[u8], out: &mut Vec<u8>) {
    let mut i = 0;
    while i < plane.len() {
        let v = plane[i];
        let run = plane[i..].iter().take(63).take_while(|&&b| b == v).count();
        if run > 1 || v >= 0xC0 {
            out.push(0xC0 | run as u8);
        }
        out.push(v);
        i += run;
    }
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let mut b = Bytes::new(bytes);
    let h = b.take(128, "the 128-byte PCX header")?;
    if h[0] != 10 {
        return Err(at(0, format!("expected the PCX marker 10, found {}", h[0])));
    }
    let le = |i: usize| usize::from(u16::from_le_bytes([h[i], h[i + 1]]));
    let (coded, bits, planes, bytes_per_line) = (h[2], h[3], h[65], le(66));
    let (x0, y0, x1, y1) = (le(4), le(6), le(8), le(10));
    if x1 < x0 || y1 < y0 {
        return Err(at(
            4,
            format!(
                "expected a window with x min ≤ x max and y min ≤ y max, found {x0}…{x1}, {y0}…{y1}"
            ),
        ));
    }
    let (width, height) = (x1 - x0 + 1, y1 - y0 + 1);
    if coded > 1 {
        return Err(at(
            2,
            format!("expected encoding 0 (none) or 1 (run lengths), found {coded}"),
        ));
    }
    if !matches!((bits, planes), (8, 1) | (8, 3) | (8, 4) | (1, 1)) {
        return Err(at(
            3,
            format!(
                "expected 8 bits in 1, 3 or 4 planes or 1 bit in 1 plane, found {bits} bits in {planes} planes"
            ),
        ));
    }
    if bytes_per_line < (width * bits as usize).div_ceil(8) {
        return Err(at(
            66,
            format!(
                "expected at least {} bytes per line for {width} pixels, found {bytes_per_line}",
                (width * bits as usize).div_ceil(8)
            ),
        ));
    }
    let mut rgb = pixels(
        width,
        height,
        b.remaining(),
        (32 * 8, usize::from(planes * bits)),
    )?;
    // An 8-bit single-plane image's palette: the last 769 bytes, marker 12 first.
    let palette = (bits == 8 && planes == 1)
        .then(|| {
            let p = bytes
                .len()
                .checked_sub(769)
                .filter(|&p| p >= 128 && bytes[p] == 12);
            p.map(|p| &bytes[p + 1..]).ok_or_else(|| {
                at(
                    bytes.len(),
                    "expected the 256-colour palette (marker 12 and 768 bytes) at the end",
                )
            })
        })
        .transpose()?;
    let line = bytes_per_line * planes as usize;
    let mut scan = vec![0u8; line];
    for y in 0..height {
        let mut n = 0;
        while n < line {
            let v = b.u8("run-length coded scanlines")?;
            let (count, value) = if coded == 1 && v >= 0xC0 {
                ((v & 0x3F) as usize, b.u8("a run's value")?)
            } else {
                (1, v)
            };
            let count = count.min(line - n);
            scan[n..n + count].fill(value);
            n += count;
        }
        for x in 0..width {
            rgb[y * width + x] = match (bits, palette) {
                (1, _) => [f32::from((scan[x / 8] >> (7 - x % 8)) & 1); 3],
                (_, Some(p)) => {
                    let i = scan[x] as usize * 3;
                    [unit(p[i]), unit(p[i + 1]), unit(p[i + 2])]
                }
                _ => [0, 1, 2].map(|c| unit(scan[c * bytes_per_line + x])),
            };
        }
    }
    Ok(Decoded { width, height, rgb })
}
