//! Amiga Interleaved Bitmap (`.iff`, `.ilbm`; Electronic Arts' "EA IFF 85" and "ILBM" documents,
//! 1985/86): a `FORM` chunk of type `ILBM` with a `BMHD` header and a `BODY`. VoRANG writes
//! "deep" 24-bit ILBM: per row, 24 bit planes (red bits 0…7, then green, then blue), each plane
//! row a multiple of 16 bits, MSB first, ByteRun1-coded ([`super::packbits`]) one plane row at a
//! time. (The thesis's `iff` was Sun's TAAC format, which nothing reads today: `.iff` now means
//! the format every reader knows by that name.) The reader takes 1 to 8 planes through a `CMAP`,
//! and 24 or 32 planes, uncompressed or ByteRun1, with or without a mask plane.

use std::io::{self, Write};

use super::{Bytes, Decoded, at, packbits, pixels, rows8, unit};
use crate::framebuffer::Framebuffer;

pub fn sniff(bytes: &[u8]) -> bool {
    bytes.len() >= 12 && &bytes[..4] == b"FORM" && &bytes[8..12] == b"ILBM"
}

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    super::check_dims(fb, i16::MAX as usize, "ILBM")?;
    let (width, height) = (fb.width as u16, fb.height as u16);
    let mut bmhd = Vec::with_capacity(20);
    bmhd.extend_from_slice(&width.to_be_bytes());
    bmhd.extend_from_slice(&height.to_be_bytes());
    bmhd.extend_from_slice(&[0, 0, 0, 0]); // position
    bmhd.extend_from_slice(&[24, 0, 1, 0]); // planes, no mask, ByteRun1, pad
    bmhd.extend_from_slice(&[0, 0, 1, 1]); // transparent colour, aspect 1:1
    bmhd.extend_from_slice(&width.to_be_bytes()); // page size
    bmhd.extend_from_slice(&height.to_be_bytes());
    let plane_row = fb.width.div_ceil(16) * 2;
    let mut body = Vec::new();
    let mut plane = vec![0u8; plane_row];
    for row in rows8(fb) {
        for c in 0..3 {
            for bit in 0..8 {
                plane.fill(0);
                for (x, p) in row.iter().enumerate() {
                    if p[c] >> bit & 1 == 1 {
                        plane[x / 8] |= 0x80 >> (x % 8);
                    }
                }
                packbits::encode(&plane, &mut body);
            }
        }
    }
    let chunk = |id: &[u8], data: &[u8], out: &mut Vec<u8>| {
        out.extend_from_slice(id);
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        out.extend_from_slice(data);
        if data.len() % 2 == 1 {
            out.push(0);
        }
    };
    let mut form = b"ILBM".to_vec();
    chunk(b"BMHD", &bmhd, &mut form);
    chunk(b"BODY", &body, &mut form);
    let size =
        u32::try_from(form.len()).map_err(|_| io::Error::other("ILBM files hold at most 4 GB"))?;
    w.write_all(b"FORM")?;
    w.write_all(&size.to_be_bytes())?;
    w.write_all(&form)
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    if !sniff(bytes) {
        return Err(at(0, "expected `FORM`, a size and `ILBM`"));
    }
    let mut b = Bytes::at(bytes, 12);
    let (mut header, mut cmap) = (None, None);
    while b.remaining() >= 8 {
        let pos = b.pos();
        let id = b.take(4, "a chunk name")?;
        let n = b.u32_be("a chunk size")? as usize;
        let data = b.take(n, "the chunk's data").map_err(|e| {
            format!(
                "{e} (chunk `{}` at byte {pos})",
                String::from_utf8_lossy(id)
            )
        })?;
        if n % 2 == 1 && b.remaining() > 0 {
            b.u8("padding")?;
        }
        match id {
            b"BMHD" => header = Some((pos + 8, data)),
            b"CMAP" => cmap = Some(data),
            b"BODY" => {
                let (hpos, h) = header
                    .ok_or_else(|| at(pos, "expected the `BMHD` header before the `BODY`"))?;
                return body(hpos, h, cmap, data, pos + 8);
            }
            _ => {}
        }
    }
    Err(at(b.pos(), "expected a `BODY` chunk"))
}

fn body(
    hpos: usize,
    h: &[u8],
    cmap: Option<&[u8]>,
    data: &[u8],
    dpos: usize,
) -> Result<Decoded, String> {
    if h.len() < 20 {
        return Err(at(
            hpos,
            format!("expected a 20-byte `BMHD`, found {} bytes", h.len()),
        ));
    }
    let width = u16::from_be_bytes([h[0], h[1]]) as usize;
    let height = u16::from_be_bytes([h[2], h[3]]) as usize;
    let (planes, masking, compression) = (h[8] as usize, h[9], h[10]);
    if !matches!(planes, 1..=8 | 24 | 32) {
        return Err(at(
            hpos + 8,
            format!("expected 1 to 8, 24 or 32 planes, found {planes}"),
        ));
    }
    if compression > 1 {
        return Err(at(
            hpos + 10,
            format!("expected compression 0 (none) or 1 (ByteRun1), found {compression}"),
        ));
    }
    let palette: Vec<[f32; 3]> = if planes <= 8 {
        let map = cmap.ok_or_else(|| {
            at(
                hpos,
                format!("expected a `CMAP` colour map for {planes} planes"),
            )
        })?;
        map.chunks_exact(3)
            .map(|c| [unit(c[0]), unit(c[1]), unit(c[2])])
            .collect()
    } else {
        Vec::new()
    };
    let plane_row = width.div_ceil(16) * 2;
    let stored = planes + usize::from(masking == 1); // a mask plane follows the colour planes
    let mut rgb = pixels(width, height, data.len(), (64 * 8, stored))?;
    let mut b = Bytes::new(data);
    let mut row = vec![0u8; plane_row * stored];
    for y in 0..height {
        for p in 0..stored {
            let dst = &mut row[p * plane_row..(p + 1) * plane_row];
            if compression == 1 {
                packbits::decode(&mut b, dst)
                    .map_err(|e| format!("`BODY` row {y}: {e} (the body starts at byte {dpos})"))?;
            } else {
                dst.copy_from_slice(b.take(plane_row, "an uncompressed plane row")?);
            }
        }
        for x in 0..width {
            let bit = |p: usize| (row[p * plane_row + x / 8] >> (7 - x % 8)) & 1;
            let value = |first: usize, n: usize| {
                (0..n).fold(0usize, |v, i| v | (bit(first + i) as usize) << i)
            };
            rgb[y * width + x] = if planes <= 8 {
                let i = value(0, planes);
                *palette.get(i).ok_or_else(|| {
                    format!(
                        "`BODY` row {y}: colour {i} is past the colour map's {} entries",
                        palette.len()
                    )
                })?
            } else {
                [0, 1, 2].map(|c| unit(value(8 * c, 8) as u8))
            };
        }
    }
    Ok(Decoded { width, height, rgb })
}
