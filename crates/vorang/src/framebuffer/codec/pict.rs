//! Apple QuickDraw picture, version 2 (`.pict`, Inside Macintosh: Imaging With QuickDraw,
//! appendix A): a 512-byte application header (zeros), the picture size and frame, then
//! big-endian opcodes. VoRANG writes the extended version-2 header and one `DirectBitsRect`
//! (opcode 0x009A): a 32-bit RGBDirect pixel map with three 8-bit components, packing type 4 —
//! each row stored as its R, G and B planes one after the other and PackBits-coded, with a byte
//! count before it (one byte where a row has at most 250 bytes, two otherwise). The reader
//! takes such pictures (and unpacked ones) — the direct-colour form that Photoshop and
//! ImageMagick also write — and skips the common header, clip and comment opcodes.
//!
//! Apple decides "unpacked rows" (row bytes < 8) and "two-byte counts" (row bytes > 250) by the
//! pixel map's row bytes, 4 × width; ImageMagick by 3 × width (rows unpacked below 8, two-byte
//! counts above 200). The two disagree for widths 1, 2 and 63…66, so for those the pixel map is
//! made wider (3 or 67 pixels, the last pixel repeated) and the source rectangle crops it back:
//! every reader then sees the same rows.

use std::io::{self, Write};

use super::{Bytes, Decoded, at, packbits, pixels, rows8, unit};
use crate::framebuffer::Framebuffer;

const DIRECT_BITS_RECT: u16 = 0x009A;
const END: u16 = 0x00FF;

fn rect(out: &mut Vec<u8>, height: u16, width: u16) {
    for v in [0, 0, height, width] {
        out.extend_from_slice(&v.to_be_bytes());
    }
}

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    // Rectangles are signed 16-bit and a row of 32-bit pixels counts its bytes in 14 bits.
    super::check_dims(fb, 4095, "PICT")?;
    let (width, height) = (fb.width as u16, fb.height as u16);
    let map_width = match width {
        1 | 2 => 3,
        63..=66 => 67,
        w => w,
    };
    let row_bytes = map_width * 4;
    let mut p = vec![0u8; 512];
    p.extend_from_slice(&[0, 0]); // picture size: set below (low 16 bits)
    rect(&mut p, height, width); // picture frame
    p.extend_from_slice(&[0x00, 0x11, 0x02, 0xFF]); // version 2
    p.extend_from_slice(&[0x0C, 0x00]); // header opcode
    p.extend_from_slice(&[0xFF, 0xFE, 0, 0]); // extended version 2
    p.extend_from_slice(&0x0048_0000u32.to_be_bytes()); // 72 dpi, as 16.16 fixed point
    p.extend_from_slice(&0x0048_0000u32.to_be_bytes());
    rect(&mut p, height, width); // source rectangle
    p.extend_from_slice(&[0; 4]);
    p.extend_from_slice(&[0x00, 0x1E]); // default highlight
    p.extend_from_slice(&[0x00, 0x01, 0x00, 0x0A]); // clip region: just a rectangle
    rect(&mut p, height, width);
    p.extend_from_slice(&DIRECT_BITS_RECT.to_be_bytes());
    p.extend_from_slice(&0xFFu32.to_be_bytes()); // base address (unused in a file)
    p.extend_from_slice(&(row_bytes | 0x8000).to_be_bytes()); // top bit: a pixel map
    rect(&mut p, height, map_width); // bounds
    p.extend_from_slice(&0u16.to_be_bytes()); // pixel map version
    p.extend_from_slice(&4u16.to_be_bytes()); // packing: component planes, PackBits
    p.extend_from_slice(&0u32.to_be_bytes()); // packed size
    p.extend_from_slice(&0x0048_0000u32.to_be_bytes());
    p.extend_from_slice(&0x0048_0000u32.to_be_bytes());
    p.extend_from_slice(&16u16.to_be_bytes()); // pixel type: RGBDirect
    p.extend_from_slice(&32u16.to_be_bytes()); // pixel size
    p.extend_from_slice(&3u16.to_be_bytes()); // components
    p.extend_from_slice(&8u16.to_be_bytes()); // bits per component
    p.extend_from_slice(&[0; 12]); // plane bytes, colour table, reserved
    rect(&mut p, height, width); // source
    rect(&mut p, height, width); // destination
    p.extend_from_slice(&0u16.to_be_bytes()); // transfer mode: srcCopy
    let map_width = usize::from(map_width);
    let mut planes = vec![0u8; 3 * map_width];
    let mut packed = Vec::new();
    for row in rows8(fb) {
        for x in 0..map_width {
            let px = row[x.min(row.len() - 1)];
            for c in 0..3 {
                planes[c * map_width + x] = px[c];
            }
        }
        packed.clear();
        packbits::encode(&planes, &mut packed);
        if row_bytes > 250 {
            p.extend_from_slice(&(packed.len() as u16).to_be_bytes());
        } else {
            p.push(packed.len() as u8);
        }
        p.extend_from_slice(&packed);
    }
    if p.len() % 2 == 1 {
        p.push(0); // opcodes start at even offsets
    }
    p.extend_from_slice(&END.to_be_bytes());
    let size = ((p.len() - 512) & 0xFFFF) as u16;
    p[512..514].copy_from_slice(&size.to_be_bytes());
    w.write_all(&p)
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    // The 512-byte header is absent in a picture taken from a resource: the version opcode
    // (0x0011 0x02FF) at byte 10 tells.
    let start = if bytes.get(10..14) == Some(&[0x00, 0x11, 0x02, 0xFF]) {
        0
    } else {
        512
    };
    let mut b = Bytes::at(bytes, start);
    b.take(10, "the picture size and frame")?;
    if b.take(4, "the version-2 opcode 0x0011 0x02FF")? != [0x00, 0x11, 0x02, 0xFF] {
        return Err(at(
            start + 10,
            "expected a version-2 picture (opcode 0x0011 0x02FF); version-1 pictures are not read",
        ));
    }
    loop {
        if b.pos() % 2 == 1 {
            b.u8("padding")?;
        }
        let pos = b.pos();
        let op = b.u16_be("an opcode")?;
        match op {
            0x0000 | 0x001E => {} // no-op, default highlight
            0x0C00 => drop(b.take(24, "the header opcode's data")?),
            0x0001 => {
                let n = b.u16_be("the clip region's size")? as usize;
                b.take(n.saturating_sub(2), "the clip region")?;
            }
            0x00A0 => drop(b.take(2, "a short comment")?),
            0x00A1 => {
                b.take(2, "a long comment's kind")?;
                let n = b.u16_be("a long comment's size")? as usize;
                b.take(n, "a long comment")?;
            }
            DIRECT_BITS_RECT => return direct_bits(&mut b),
            END => {
                return Err(at(
                    pos,
                    "the picture ends without a DirectBitsRect (0x009A) image",
                ));
            }
            _ => {
                return Err(at(
                    pos,
                    format!(
                        "opcode 0x{op:04X} is not read: VoRANG reads 32-bit direct-colour pictures (DirectBitsRect, 0x009A)"
                    ),
                ));
            }
        }
    }
}

fn direct_bits(b: &mut Bytes) -> Result<Decoded, String> {
    b.u32_be("the base address")?;
    let row_pos = b.pos();
    let row_bytes = (b.u16_be("the row bytes")? & 0x3FFF) as usize;
    let bounds = b.take(8, "the bounds rectangle")?;
    let side = |i: usize| i16::from_be_bytes([bounds[i], bounds[i + 1]]) as isize;
    let (height, width) = (side(4) - side(0), side(6) - side(2));
    if width <= 0 || height <= 0 {
        return Err(at(
            row_pos + 2,
            format!("expected a non-empty bounds rectangle, found {width} × {height}"),
        ));
    }
    let (width, height) = (width as usize, height as usize);
    b.u16_be("the pixel map version")?;
    let pack_pos = b.pos();
    let pack = b.u16_be("the packing type")?;
    b.take(12, "the packed size and resolution")?;
    b.u16_be("the pixel type")?;
    let size_pos = b.pos();
    let pixel_size = b.u16_be("the pixel size")?;
    let components = b.u16_be("the component count")? as usize;
    b.u16_be("the component size")?;
    b.take(12, "the plane bytes, colour table and reserved fields")?;
    let src_pos = b.pos();
    let src = b.take(8, "the source rectangle")?;
    b.take(10, "the destination rectangle and transfer mode")?;
    let src = |i: usize| i16::from_be_bytes([src[i], src[i + 1]]) as isize;
    // The part of the pixel map that is the picture, relative to the map's top left.
    let (top, left) = (src(0) - side(0), src(2) - side(2));
    let (bottom, right) = (src(4) - side(0), src(6) - side(2));
    if top < 0
        || left < 0
        || bottom <= top
        || right <= left
        || bottom as usize > height
        || right as usize > width
    {
        return Err(at(
            src_pos,
            format!("expected a source rectangle inside the {width} × {height} pixel map"),
        ));
    }
    if pixel_size != 32 || !matches!(components, 3 | 4) {
        return Err(at(
            size_pos,
            format!(
                "expected 32-bit pixels with 3 or 4 components, found {pixel_size}-bit with {components}"
            ),
        ));
    }
    if row_bytes < 4 * width {
        return Err(at(
            row_pos,
            format!(
                "expected at least {} row bytes for {width} pixels, found {row_bytes}",
                4 * width
            ),
        ));
    }
    let mut rgb = pixels(width, height, b.remaining(), (64, 3))?;
    let unpacked = row_bytes < 8 || pack == 1 || pack == 2;
    if !unpacked && pack != 4 && pack != 0 {
        return Err(at(
            pack_pos,
            format!("expected packing type 0, 1, 2 or 4, found {pack}"),
        ));
    }
    let mut planes = vec![0u8; components * width];
    for y in 0..height {
        if unpacked {
            // Chunky pixels x R G B (packing 2 drops the pad byte).
            let n = if pack == 2 { 3 } else { 4 };
            let row = b.take(
                if pack == 2 { 3 * width } else { row_bytes },
                "an unpacked row",
            )?;
            for x in 0..width {
                let p = &row[x * n + n - 3..x * n + n];
                rgb[y * width + x] = [unit(p[0]), unit(p[1]), unit(p[2])];
            }
            continue;
        }
        let count = if row_bytes > 250 {
            b.u16_be("a row's byte count")? as usize
        } else {
            b.u8("a row's byte count")? as usize
        };
        let row = b.take(count, "a packed row")?;
        packbits::decode(&mut Bytes::new(row), &mut planes).map_err(|e| format!("row {y}: {e}"))?;
        let skip = components - 3; // an alpha plane comes first
        for x in 0..width {
            rgb[y * width + x] = [0, 1, 2].map(|c| unit(planes[(skip + c) * width + x]));
        }
    }
    let (w, h) = ((right - left) as usize, (bottom - top) as usize);
    let (top, left) = (top as usize, left as usize);
    let rgb = (0..h)
        .flat_map(|y| rgb[(top + y) * width + left..][..w].to_vec())
        .collect();
    Ok(Decoded {
        width: w,
        height: h,
        rgb,
    })
}
