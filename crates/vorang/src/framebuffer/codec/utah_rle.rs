//! Utah Raster Toolkit run-length encoded image (`.rle`, the thesis's `rlc`; Spencer W. Thomas,
//! "Design of the Utah RLE Format", 1986): a little-endian header (magic 0xCC52, position, size,
//! flags, colour count, bits per pixel, colour map), then a stream of operations — choose a
//! channel, skip lines or pixels, literal bytes, runs — building the image from the **bottom**
//! row up. VoRANG writes 3 channels of 8 bits, no background and no colour map, each row as one
//! literal byte block per channel (a valid file of the format; its runs are optional). The reader
//! takes every operation, 1 or 3 channels (alpha ignored), and fills what the file skips with its
//! background colour (black without one).

use std::io::{self, Write};

use super::{Bytes, Decoded, at, pixels, rows8, unit};
use crate::framebuffer::Framebuffer;

const MAGIC: u16 = 0xCC52;
const NO_BACKGROUND: u8 = 0x2;
const COMMENT: u8 = 0x8;
const LONG: u8 = 0x40;
const SKIP_LINES: u8 = 1;
const SET_COLOR: u8 = 2;
const SKIP_PIXELS: u8 = 3;
const BYTE_DATA: u8 = 5;
const RUN_DATA: u8 = 6;
const EOF: u8 = 7;

pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC.to_le_bytes())
}

/// An operation with its operand, in the short form where it fits a byte.
fn op(out: &mut Vec<u8>, code: u8, operand: usize) {
    if operand <= 255 {
        out.extend_from_slice(&[code, operand as u8]);
    } else {
        out.extend_from_slice(&[code | LONG, 0]);
        out.extend_from_slice(&(operand as u16).to_le_bytes());
    }
}

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    // Positions and sizes are 16-bit; the operand of a long operation too.
    super::check_dims(fb, i16::MAX as usize, "Utah RLE")?;
    let mut h = Vec::with_capacity(16);
    h.extend_from_slice(&MAGIC.to_le_bytes());
    h.extend_from_slice(&[0, 0, 0, 0]); // x, y position
    h.extend_from_slice(&(fb.width as u16).to_le_bytes());
    h.extend_from_slice(&(fb.height as u16).to_le_bytes());
    h.extend_from_slice(&[NO_BACKGROUND, 3, 8, 0, 0]); // flags, channels, bits, no colour map
    h.push(0); // filler in place of the background colour
    w.write_all(&h)?;
    let rows: Vec<Vec<[u8; 3]>> = rows8(fb).collect();
    let mut out = Vec::new();
    for (i, row) in rows.iter().rev().enumerate() {
        out.clear();
        if i > 0 {
            op(&mut out, SKIP_LINES, 1);
        }
        for c in 0..3 {
            op(&mut out, SET_COLOR, c);
            op(&mut out, BYTE_DATA, row.len() - 1);
            out.extend(row.iter().map(|p| p[c]));
            if row.len() % 2 == 1 {
                out.push(0); // literal data is padded to 16 bits
            }
        }
        w.write_all(&out)?;
    }
    w.write_all(&[EOF, 0])
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let mut b = Bytes::new(bytes);
    if b.u16_le("the Utah RLE magic number")? != MAGIC {
        return Err(at(0, "expected the Utah RLE magic number 0xCC52"));
    }
    // The position says where the image sat on a screen: the picture starts at its corner.
    b.take(4, "the x and y position")?;
    let width = b.u16_le("the width")? as usize;
    let height = b.u16_le("the height")? as usize;
    let flags = b.u8("the flags")?;
    let channels = b.u8("the channel count")? as usize;
    let bits = b.u8("the bits per pixel")?;
    let maps = b.u8("the colour map count")? as usize;
    let map_bits = b.u8("the colour map length (log 2)")?;
    if bits != 8 {
        return Err(at(12, format!("expected 8 bits per pixel, found {bits}")));
    }
    if channels != 1 && channels != 3 {
        return Err(at(
            11,
            format!("expected 1 or 3 channels, found {channels}"),
        ));
    }
    if map_bits > 8 {
        return Err(at(
            14,
            format!("expected a colour map of at most 2^8 entries, found 2^{map_bits}"),
        ));
    }
    let mut background = [0.0f32; 3];
    if flags & NO_BACKGROUND != 0 {
        b.u8("the filler byte")?;
    } else {
        let bg = b.take(channels, "the background colour")?;
        for c in 0..3 {
            background[c] = unit(bg[c.min(channels - 1)]);
        }
        if channels.is_multiple_of(2) {
            b.u8("padding")?;
        }
    }
    b.take(maps * (2 << map_bits), "the colour map")?;
    if flags & COMMENT != 0 {
        let n = b.u16_le("the comment length")? as usize;
        b.take(n + n % 2, "the comment")?;
    }
    // Runs and skipped lines cost a few bytes for any number of pixels: the bound is loose.
    let mut rgb = pixels(width, height, b.remaining(), (2048, 1))?;
    rgb.fill(background);
    let (mut line, mut x, mut channel) = (0usize, 0usize, 0usize);
    // Sets channel `channel` of pixels x.. of the current line (counted from the bottom);
    // values outside the image are dropped, as the toolkit's readers do.
    let mut put = |line: usize, x: usize, values: &mut dyn Iterator<Item = u8>, channel: usize| {
        for (i, v) in values.enumerate() {
            if channel < 3 && line < height && x + i < width {
                let p = &mut rgb[(height - 1 - line) * width + x + i];
                if channels == 1 {
                    *p = [unit(v); 3];
                } else {
                    p[channel] = unit(v);
                }
            }
        }
    };
    loop {
        let pos = b.pos();
        let code = b.u8("an operation")?;
        let short = b.u8("an operand")? as usize;
        let operand = if code & LONG != 0 {
            b.u16_le("a long operand")? as usize
        } else {
            short
        };
        match code & !LONG {
            SKIP_LINES => {
                line += operand;
                x = 0;
            }
            SET_COLOR => {
                channel = operand;
                x = 0;
            }
            SKIP_PIXELS => x += operand,
            BYTE_DATA => {
                let n = operand + 1;
                let data = b.take(n + n % 2, "literal pixel bytes")?;
                put(line, x, &mut data[..n].iter().copied(), channel);
                x += n;
            }
            RUN_DATA => {
                let n = operand + 1;
                let v = b.take(2, "a run's value")?[0];
                put(line, x, &mut std::iter::repeat_n(v, n.min(width)), channel);
                x += n;
            }
            EOF => break,
            other => {
                return Err(at(
                    pos,
                    format!("expected an operation 1 to 7, found {other}"),
                ));
            }
        }
        if line > height {
            break;
        }
    }
    Ok(Decoded { width, height, rgb })
}
