//! X Window System window dump (`.xwd`, X11's `XWDFile.h`, file version 7): a header of 25
//! 32-bit fields and a window name, an optional colour map, then the pixels. VoRANG writes a
//! big-endian 24-bit TrueColor ZPixmap with 32 bits per pixel (`0x00RRGGBB`, what `xwd` itself
//! writes on today's displays) and no colour map. The reader takes ZPixmaps of 8 (through the
//! colour map), 16, 24 or 32 bits per pixel in either byte order.

use std::io::{self, Write};

use super::{Bytes, Decoded, at, pixels, rows8};
use crate::framebuffer::Framebuffer;

const NAME: &[u8] = b"vorang\0";
const ZPIXMAP: u32 = 2;
const TRUE_COLOR: u32 = 4;
const DIRECT_COLOR: u32 = 5;

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    super::check_dims(fb, (u32::MAX / 4) as usize, "XWD")?;
    let (width, height) = (fb.width as u32, fb.height as u32);
    #[rustfmt::skip]
    let header: [u32; 25] = [
        100 + NAME.len() as u32, // header size, with the window name
        7,                       // file version
        ZPIXMAP,                 // pixmap format
        24,                      // depth
        width, height,
        0,                       // x offset
        1,                       // byte order: most significant byte first
        32, 1, 32,               // bitmap unit, bit order (MSB first), scanline pad
        32,                      // bits per pixel
        width * 4,               // bytes per line
        TRUE_COLOR,              // visual class
        0xff_0000, 0xff00, 0xff, // red, green, blue masks
        8,                       // bits per RGB
        256,                     // colour map entries of the visual
        0,                       // colours stored in the file
        width, height, 0, 0, 0,  // window width, height, x, y, border width
    ];
    for v in header {
        w.write_all(&v.to_be_bytes())?;
    }
    w.write_all(NAME)?;
    let mut row = Vec::with_capacity(fb.width * 4);
    for line in rows8(fb) {
        row.clear();
        row.extend(line.iter().flat_map(|[r, g, b]| [0, *r, *g, *b]));
        w.write_all(&row)?;
    }
    Ok(())
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    // The header is in the writer's byte order: version 7 tells which.
    let big = match bytes.get(4..8) {
        Some([0, 0, 0, 7]) => true,
        Some([7, 0, 0, 0]) => false,
        _ => return Err(at(4, "expected the XWD file version 7")),
    };
    let mut b = Bytes::new(bytes);
    let mut h = [0u32; 25];
    for (i, v) in h.iter_mut().enumerate() {
        let what = format!("XWD header field {}", i + 1);
        *v = if big {
            b.u32_be(&what)?
        } else {
            b.u32_le(&what)?
        };
    }
    let field = |i: usize| h[i] as usize;
    let (header_size, format, width, height) = (field(0), h[2], field(4), field(5));
    let (msb_first, bpp, bytes_per_line) = (h[7] == 1, field(11), field(12));
    let (class, masks, ncolors) = (h[13], [h[14], h[15], h[16]], field(19));
    if format != ZPIXMAP {
        return Err(at(
            8,
            format!("expected a ZPixmap (format 2), found format {format}"),
        ));
    }
    if !matches!(bpp, 8 | 16 | 24 | 32) {
        return Err(at(
            44,
            format!("expected 8, 16, 24 or 32 bits per pixel, found {bpp}"),
        ));
    }
    if header_size < 100 {
        return Err(at(
            0,
            format!("expected a header size of at least 100, found {header_size}"),
        ));
    }
    let mut b = Bytes::at(bytes, header_size);
    let mut colormap = Vec::new();
    for _ in 0..ncolors.min(b.remaining() / 12 + 1) {
        let e = b.take(12, "an XWD colour map entry")?;
        let get = |i: usize| {
            let v = [e[i], e[i + 1]];
            f32::from(if big {
                u16::from_be_bytes(v)
            } else {
                u16::from_le_bytes(v)
            }) / 65535.0
        };
        let pixel = if big {
            u32::from_be_bytes([e[0], e[1], e[2], e[3]])
        } else {
            u32::from_le_bytes([e[0], e[1], e[2], e[3]])
        };
        colormap.push((pixel, [get(4), get(6), get(8)]));
    }
    if bytes_per_line < width.saturating_mul(bpp).div_ceil(8) {
        return Err(at(
            48,
            format!(
                "expected at least {} bytes per line for {width} pixels of {bpp} bits, found {bytes_per_line}",
                width.saturating_mul(bpp).div_ceil(8)
            ),
        ));
    }
    let mut rgb = pixels(width, height, b.remaining(), (8, bpp))?;
    let masked = matches!(class, TRUE_COLOR | DIRECT_COLOR) && bpp > 8;
    for y in 0..height {
        let line = b.take(bytes_per_line, "a row of pixels")?;
        for x in 0..width {
            let px = &line[x * bpp / 8..(x + 1) * bpp / 8];
            let v = if msb_first {
                px.iter().fold(0u32, |a, &c| a << 8 | u32::from(c))
            } else {
                px.iter().rev().fold(0u32, |a, &c| a << 8 | u32::from(c))
            };
            rgb[y * width + x] = if masked {
                masks.map(|m| {
                    if m == 0 {
                        0.0
                    } else {
                        ((v & m) >> m.trailing_zeros()) as f32 / (m >> m.trailing_zeros()) as f32
                    }
                })
            } else {
                colormap
                    .iter()
                    .find(|(p, _)| *p == v)
                    .map(|c| c.1)
                    .ok_or_else(|| {
                        format!(
                            "row {y}: pixel value {v} is not in the colour map ({} entries)",
                            colormap.len()
                        )
                    })?
            };
        }
    }
    Ok(Decoded { width, height, rgb })
}
