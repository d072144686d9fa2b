//! SGI image files (`.rgb`, the thesis's example format; Paul Haeberli's specification, "The
//! SGI Image File Format", version 1.00): a 512-byte big-endian header, then channel planes,
//! each from the bottom row up. VoRANG writes them uncompressed; the reader also takes the
//! run-length coded storage, 1 to 4 channels (grey, grey + alpha, RGB, RGBA; alpha ignored) and
//! 16-bit channels.

use std::io::{self, Write};

use super::{Bytes, Decoded, at, pixels};
use crate::framebuffer::{Framebuffer, to_u8};

pub fn sniff(bytes: &[u8]) -> bool {
    bytes.starts_with(&474u16.to_be_bytes())
}

pub fn write(fb: &Framebuffer, w: &mut impl Write, alpha: bool) -> io::Result<()> {
    let too_big = |n: usize| n == 0 || n > u16::MAX as usize;
    if too_big(fb.width) || too_big(fb.height) {
        return Err(io::Error::other(
            "SGI images are at most 65535 × 65535 pixels",
        ));
    }
    let channels: u16 = if alpha { 4 } else { 3 };
    let mut h = Vec::with_capacity(512);
    h.extend_from_slice(&474u16.to_be_bytes()); // magic
    h.push(0); // storage: verbatim
    h.push(1); // bytes per channel
    h.extend_from_slice(&3u16.to_be_bytes()); // dimension
    h.extend_from_slice(&(fb.width as u16).to_be_bytes());
    h.extend_from_slice(&(fb.height as u16).to_be_bytes());
    h.extend_from_slice(&channels.to_be_bytes());
    h.extend_from_slice(&0u32.to_be_bytes()); // pixmin
    h.extend_from_slice(&255u32.to_be_bytes()); // pixmax
    h.extend_from_slice(&[0; 4]);
    let mut name = [0u8; 80];
    name[..6].copy_from_slice(b"vorang");
    h.extend_from_slice(&name);
    h.extend_from_slice(&0u32.to_be_bytes()); // colormap: normal
    h.resize(512, 0);
    w.write_all(&h)?;
    let mut row = vec![0u8; fb.width];
    for c in 0..channels as usize {
        for y in (0..fb.height).rev() {
            for (x, r) in row.iter_mut().enumerate() {
                let p = &fb.pixels[y * fb.width + x];
                // With an alpha plane the file's convention applies; without, the framebuffer's
                // composited RGB.
                *r = to_u8(if alpha { fb.output_pixel(p)[c] } else { p[c] });
            }
            w.write_all(&row)?;
        }
    }
    Ok(())
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let mut b = Bytes::new(bytes);
    if b.u16_be("the SGI magic number")? != 474 {
        return Err(at(0, "expected the SGI magic number 474"));
    }
    let rle = b.u8("the storage format")?;
    let bpc = b.u8("the bytes per channel")? as usize;
    let _dimension = b.u16_be("the dimension")?;
    let width = b.u16_be("the width")? as usize;
    let height = b.u16_be("the height")? as usize;
    let channels = b.u16_be("the channel count")? as usize;
    b.take(12, "the minimum and maximum pixel values")?;
    b.take(84, "the image name")?;
    let colormap = b.u32_be("the colour map type")?;
    if rle > 1 {
        return Err(at(
            2,
            format!("expected storage 0 (verbatim) or 1 (RLE), found {rle}"),
        ));
    }
    if bpc != 1 && bpc != 2 {
        return Err(at(
            3,
            format!("expected 1 or 2 bytes per channel, found {bpc}"),
        ));
    }
    if !(1..=4).contains(&channels) {
        return Err(at(
            10,
            format!("expected 1 to 4 channels, found {channels}"),
        ));
    }
    if colormap != 0 {
        return Err(at(
            104,
            format!("expected colour map type 0 (normal pixels), found {colormap}"),
        ));
    }
    // Grey images fill all three colours from channel 0; alpha (channel 1 or 3) is skipped.
    let used = if channels < 3 { 1 } else { 3 };
    // A run of up to 127 values costs two codes.
    let expansion = if rle == 1 { 64 } else { 1 };
    let mut rgb = pixels(width, height, bytes.len(), (expansion, bpc * used))?;
    let max = if bpc == 1 { 255.0 } else { 65535.0 };
    let mut row = vec![0u16; width];
    for c in 0..used {
        for r in 0..height {
            if rle == 1 {
                let table = 512 + 4 * (c * height + r);
                let mut t = Bytes::at(bytes, table);
                let start = t.u32_be("an RLE row offset")? as usize;
                let mut t = Bytes::at(bytes, table + 4 * height * channels);
                let _len = t.u32_be("an RLE row length")?;
                unpack(&mut Bytes::at(bytes, start), bpc, &mut row)
                    .map_err(|e| format!("channel {c}, row {r} (from the bottom): {e}"))?;
            } else {
                let start = 512 + ((c * height + r) * width) * bpc;
                let mut d = Bytes::at(bytes, start);
                for v in row.iter_mut() {
                    *v = if bpc == 1 {
                        u16::from(d.u8("a pixel")?)
                    } else {
                        d.u16_be("a pixel")?
                    };
                }
            }
            let y = height - 1 - r;
            for (x, v) in row.iter().enumerate() {
                let p = &mut rgb[y * width + x];
                let v = f32::from(*v) / max;
                if used == 1 {
                    *p = [v; 3];
                } else {
                    p[c] = v;
                }
            }
        }
    }
    Ok(Decoded { width, height, rgb })
}

/// One run-length coded row: a count byte (or word) whose top bit means "copy the next count
/// values", otherwise "repeat the next value count times"; count 0 ends the row.
fn unpack(b: &mut Bytes, bpc: usize, row: &mut [u16]) -> Result<(), String> {
    let next = |b: &mut Bytes| -> Result<u16, String> {
        if bpc == 1 {
            Ok(u16::from(b.u8("RLE data")?))
        } else {
            b.u16_be("RLE data")
        }
    };
    let mut n = 0;
    loop {
        let pos = b.pos();
        let code = next(b)?;
        let count = (code & 0x7f) as usize;
        if count == 0 {
            break;
        }
        if n + count > row.len() {
            return Err(at(
                pos,
                format!("a run of {count} overflows the row of {}", row.len()),
            ));
        }
        if code & 0x80 != 0 {
            for v in &mut row[n..n + count] {
                *v = next(b)?;
            }
        } else {
            let v = next(b)?;
            row[n..n + count].fill(v);
        }
        n += count;
    }
    if n != row.len() {
        return Err(format!("the row has {n} of {} values", row.len()));
    }
    Ok(())
}
