//! X11 bitmap (`.xbm`, Xlib's `XWriteBitmapFile` format; X Window System Protocol, "Bitmap
//! file format"): C source text with `#define NAME_width`, `#define NAME_height` and a
//! `static unsigned char NAME_bits[]` array. 1 bit per pixel, **1 = foreground (black)**, the
//! first pixel of a row in the least significant bit, rows padded to whole bytes. The picture
//! becomes black and white by the luminance threshold of [`super::is_white`]. The reader also
//! takes X10 bitmaps (`short` arrays, 16-bit words).

use std::io::{self, Write};

use super::{Decoded, is_white, pixels};
use crate::framebuffer::Framebuffer;

/// The C identifier prefix in the files VoRANG writes.
const NAME: &str = "vorang";

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    writeln!(w, "#define {NAME}_width {}", fb.width)?;
    writeln!(w, "#define {NAME}_height {}", fb.height)?;
    write!(w, "static unsigned char {NAME}_bits[] = {{")?;
    let per_row = fb.width.div_ceil(8);
    let total = per_row * fb.height;
    let mut n = 0;
    for line in fb.pixels.chunks(fb.width.max(1)) {
        for byte in 0..per_row {
            let mut b = 0u8;
            for bit in 0..8 {
                let x = byte * 8 + bit;
                if x < line.len() && !is_white(&line[x]) {
                    b |= 1 << bit;
                }
            }
            let sep = if n % 12 == 0 { "\n   " } else { " " };
            n += 1;
            let comma = if n < total { "," } else { "" };
            write!(w, "{sep}0x{b:02x}{comma}")?;
        }
    }
    writeln!(w, " }};")?;
    Ok(())
}

/// Reads an X11 (or X10) bitmap: black where a bit is set, white elsewhere.
pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        format!(
            "byte {}: expected the text of an X bitmap, found bytes that are not UTF-8",
            e.valid_up_to()
        )
    })?;
    let line_of = |offset: usize| text[..offset].matches('\n').count() + 1;
    let (mut width, mut height) = (None, None);
    let mut array = None;
    let mut offset = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.first() == Some(&"#define") {
            let bad = || format!("line {}: expected `#define NAME_width N`", i + 1);
            let (name, value) = match words.as_slice() {
                [_, name, value] => (*name, value.parse::<usize>().map_err(|_| bad())?),
                _ => return Err(bad()),
            };
            if name.ends_with("_width") || name == "width" {
                width = Some(value);
            } else if name.ends_with("_height") || name == "height" {
                height = Some(value);
            }
        } else if line.contains('[') && line.contains('{') {
            let wide = words.contains(&"short");
            if !wide && !words.contains(&"char") {
                return Err(format!(
                    "line {}: expected `static unsigned char NAME_bits[] = {{`",
                    i + 1
                ));
            }
            array = Some((offset + line.find('{').unwrap_or(0) + 1, wide));
            break;
        }
        offset += line.len();
    }
    let missing = |what: &str| format!("line 1: expected `#define NAME_{what} N` before the bits");
    let width = width.ok_or_else(|| missing("width"))?;
    let height = height.ok_or_else(|| missing("height"))?;
    let (start, wide) = array.ok_or_else(|| {
        format!(
            "line {}: expected `static unsigned char NAME_bits[] = {{`",
            line_of(text.len())
        )
    })?;
    let word_bits = if wide { 16 } else { 8 };
    let per_row = width.div_ceil(word_bits);
    let mut rgb = pixels(width, height, bytes.len(), (8, 4))?;
    let body = &text[start..];
    let end = body.find('}').ok_or_else(|| {
        format!(
            "line {}: expected `}};` after the bits",
            line_of(text.len())
        )
    })?;
    let mut words = 0;
    let mut pos = start;
    for item in body[..end].split(',') {
        let item_start = pos + (item.len() - item.trim_start().len());
        pos += item.len() + 1;
        let item = item.trim();
        if item.is_empty() {
            continue;
        }
        let hex = item
            .strip_prefix("0x")
            .or_else(|| item.strip_prefix("0X"))
            .and_then(|h| u32::from_str_radix(h, 16).ok())
            .filter(|v| *v < 1 << word_bits)
            .ok_or_else(|| {
                format!(
                    "line {}: expected a {word_bits}-bit hexadecimal value like 0x1f, found `{item}`",
                    line_of(item_start)
                )
            })?;
        let (y, x0) = (words / per_row, (words % per_row) * word_bits);
        if y >= height {
            return Err(format!(
                "line {}: more values than {width} × {height} pixels need",
                line_of(item_start)
            ));
        }
        for bit in 0..word_bits {
            if x0 + bit < width {
                let v = if hex & (1 << bit) != 0 { 0.0 } else { 1.0 };
                rgb[y * width + x0 + bit] = [v; 3];
            }
        }
        words += 1;
    }
    if words != per_row * height {
        return Err(format!(
            "line {}: expected {} values for {width} × {height} pixels, found {words}",
            line_of(start + end),
            per_row * height
        ));
    }
    Ok(Decoded { width, height, rgb })
}
