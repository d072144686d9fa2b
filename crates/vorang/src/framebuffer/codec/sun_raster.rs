//! Sun rasterfile (`.ras`, SunOS `<rasterfile.h>`, rasterfile(5)): eight big-endian 32-bit
//! header fields, an optional colour map, then rows padded to 16 bits. VoRANG writes the
//! standard type (1) at 24 bits per pixel, which stores each pixel as **B, G, R** (the type-3
//! "RGB" variant is the one with red first). The reader takes depths 1, 8 (grey or through the
//! colour map), 24 and 32, types 0 (old), 1 (standard), 2 (byte-encoded run lengths) and 3 (RGB).

use std::io::{self, Write};

use super::{Bytes, Decoded, at, pixels, rows8, unit};
use crate::framebuffer::Framebuffer;

const MAGIC: u32 = 0x59a6_6a95;
const RT_STANDARD: u32 = 1;
const RT_BYTE_ENCODED: u32 = 2;
const RT_FORMAT_RGB: u32 = 3;

pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC.to_be_bytes())
}

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    let line = (fb.width * 3).next_multiple_of(2);
    let length = line
        .checked_mul(fb.height)
        .filter(|n| *n <= u32::MAX as usize)
        .ok_or_else(|| io::Error::other("Sun raster images hold at most 4 GB of pixels"))?;
    super::check_dims(fb, u32::MAX as usize, "Sun raster")?;
    let header = [
        MAGIC,
        fb.width as u32,
        fb.height as u32,
        24,
        length as u32,
        RT_STANDARD,
        0,
        0,
    ];
    for v in header {
        w.write_all(&v.to_be_bytes())?;
    }
    let mut row = Vec::with_capacity(line);
    for pixels in rows8(fb) {
        row.clear();
        row.extend(pixels.iter().flat_map(|[r, g, b]| [*b, *g, *r]));
        row.resize(line, 0);
        w.write_all(&row)?;
    }
    Ok(())
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let mut b = Bytes::new(bytes);
    if b.u32_be("the Sun raster magic number")? != MAGIC {
        return Err(at(0, "expected the Sun raster magic number 0x59a66a95"));
    }
    let width = b.u32_be("the width")? as usize;
    let height = b.u32_be("the height")? as usize;
    let depth = b.u32_be("the depth")? as usize;
    let _length = b.u32_be("the data length")?;
    let kind = b.u32_be("the raster type")?;
    let map_type = b.u32_be("the colour map type")?;
    let map_length = b.u32_be("the colour map length")? as usize;
    if !matches!(depth, 1 | 8 | 24 | 32) {
        return Err(at(
            12,
            format!("expected a depth of 1, 8, 24 or 32 bits, found {depth}"),
        ));
    }
    if kind > RT_FORMAT_RGB {
        return Err(at(20, format!("expected raster type 0 to 3, found {kind}")));
    }
    let map = b.take(map_length, "the colour map")?;
    let palette: Vec<[f32; 3]> = match map_type {
        0 => Vec::new(),
        1 => {
            let n = map_length / 3;
            (0..n)
                .map(|i| [unit(map[i]), unit(map[n + i]), unit(map[2 * n + i])])
                .collect()
        }
        t => {
            return Err(at(
                24,
                format!("expected colour map type 0 (none) or 1 (RGB), found {t}"),
            ));
        }
    };
    let line = width.saturating_mul(depth).div_ceil(8).next_multiple_of(2);
    // A run of up to 256 bytes costs three.
    let expansion = if kind == RT_BYTE_ENCODED { 86 } else { 1 };
    let mut rgb = pixels(width, height, b.remaining(), (expansion * 8, depth))?;
    let data = if kind == RT_BYTE_ENCODED {
        unpack(&mut b, line * height)?
    } else {
        b.take(line * height, "the pixel rows")?.to_vec()
    };
    let bgr = kind != RT_FORMAT_RGB;
    for (y, row) in data.chunks(line).enumerate() {
        for x in 0..width {
            rgb[y * width + x] = match depth {
                1 => {
                    let bit = (row[x / 8] >> (7 - x % 8)) & 1;
                    match palette.get(bit as usize) {
                        Some(c) => *c,
                        None => [1.0 - f32::from(bit); 3], // 1 = black
                    }
                }
                8 => match palette.get(row[x] as usize) {
                    Some(c) => *c,
                    None if palette.is_empty() => [unit(row[x]); 3],
                    None => {
                        return Err(format!(
                            "row {y}: colour index {} is past the colour map's {} entries",
                            row[x],
                            palette.len()
                        ));
                    }
                },
                _ => {
                    let n = depth / 8;
                    let p = &row[x * n + n - 3..x * n + n];
                    let c = [unit(p[0]), unit(p[1]), unit(p[2])];
                    if bgr { [c[2], c[1], c[0]] } else { c }
                }
            };
        }
    }
    Ok(Decoded { width, height, rgb })
}

/// The byte-encoded type: 0x80 0 is one 0x80, 0x80 n v is n + 1 copies of v, any other byte
/// stands for itself.
fn unpack(b: &mut Bytes, n: usize) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    out.try_reserve_exact(n)
        .map_err(|_| "not enough memory for the pixel rows".to_string())?;
    while out.len() < n {
        let v = b.u8("run-length coded pixel rows")?;
        if v != 0x80 {
            out.push(v);
            continue;
        }
        match b.u8("a run length")? {
            0 => out.push(0x80),
            count => {
                let v = b.u8("a run's value")?;
                out.extend(std::iter::repeat_n(
                    v,
                    (count as usize + 1).min(n - out.len()),
                ));
            }
        }
    }
    Ok(out)
}
