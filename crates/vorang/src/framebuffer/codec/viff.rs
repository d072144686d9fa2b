//! Khoros Visualization Image File Format (`.viff`, `.xv`; Khoros 1 "viff.h", VIFF version 3):
//! a 1024-byte header, then the data bands one after the other, each row by row from the top.
//! VoRANG writes three bands of unsigned bytes (R, G, B), colour model "generic RGB", no map,
//! big-endian (IEEE) header. The reader takes 1 (grey), 3 or 4 (alpha ignored) byte bands
//! without a map, in either byte order.

use std::io::{self, Write};

use super::{Bytes, Decoded, at, pixels, rows8, unit};
use crate::framebuffer::Framebuffer;

const IDENTIFIER: u8 = 0xAB;
const DEP_IEEE: u8 = 0x2;
const LOC_IMPLICIT: u32 = 1;
const TYP_1_BYTE: u32 = 1;
const CM_GENERIC_RGB: u32 = 15;

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    super::check_dims(fb, u32::MAX as usize, "VIFF")?;
    let mut h = vec![IDENTIFIER, 1, 1, 3, DEP_IEEE, 0, 0, 0];
    let mut comment = [0u8; 512];
    comment[..13].copy_from_slice(b"VoRANG render");
    h.extend_from_slice(&comment);
    let words: [u32; 21] = [
        fb.width as u32,  // row size: pixels per row
        fb.height as u32, // column size: rows
        0,                // subrow size
        0,                // start x
        0,                // start y
        1.0f32.to_bits(), // pixel width
        1.0f32.to_bits(), // pixel height
        LOC_IMPLICIT,     // location type
        0,                // location dimension
        1,                // images
        3,                // data bands
        TYP_1_BYTE,       // data storage type
        0,                // encoding: raw
        0,                // map scheme: none
        0,                // map storage type: none
        0,                // map row size
        0,                // map column size
        0,                // map subrow size
        0,                // map enable
        0,                // maps per cycle
        CM_GENERIC_RGB,   // colour space model
    ];
    for v in words {
        h.extend_from_slice(&v.to_be_bytes());
    }
    h.resize(1024, 0);
    w.write_all(&h)?;
    let rows: Vec<Vec<[u8; 3]>> = rows8(fb).collect();
    let mut band = Vec::with_capacity(fb.width * fb.height);
    for c in 0..3 {
        band.clear();
        band.extend(rows.iter().flatten().map(|p| p[c]));
        w.write_all(&band)?;
    }
    Ok(())
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let mut b = Bytes::new(bytes);
    let head = b.take(8, "the VIFF identification")?;
    if head[0] != IDENTIFIER || head[1] != 1 {
        return Err(at(0, "expected the VIFF identifier 0xAB and file type 1"));
    }
    let little = matches!(head[4], 0x4 | 0x8);
    b.take(512, "the comment")?;
    let mut f = [0u32; 21];
    for (i, v) in f.iter_mut().enumerate() {
        let what = format!("VIFF header field {}", i + 1);
        *v = if little {
            b.u32_le(&what)?
        } else {
            b.u32_be(&what)?
        };
    }
    let field = |i: usize| 520 + 4 * i;
    let (width, height) = (f[0] as usize, f[1] as usize);
    let (images, bands, storage, encoding, map) = (f[9], f[10] as usize, f[11], f[12], f[13]);
    if images != 1 {
        return Err(at(field(9), format!("expected one image, found {images}")));
    }
    if !matches!(bands, 1 | 3 | 4) {
        return Err(at(
            field(10),
            format!("expected 1, 3 or 4 data bands, found {bands}"),
        ));
    }
    if storage != TYP_1_BYTE {
        return Err(at(
            field(11),
            format!("expected 1-byte data (storage type 1), found type {storage}"),
        ));
    }
    if encoding != 0 {
        return Err(at(
            field(12),
            format!("expected raw data (encoding 0), found {encoding}"),
        ));
    }
    if map != 0 {
        return Err(at(
            field(13),
            format!("expected no colour map (scheme 0), found scheme {map}"),
        ));
    }
    let mut b = Bytes::at(bytes, 1024);
    let mut rgb = pixels(width, height, b.remaining(), (1, bands))?;
    let n = width * height;
    let data = b.take(n * bands, "the data bands")?;
    for (i, p) in rgb.iter_mut().enumerate() {
        *p = if bands == 1 {
            [unit(data[i]); 3]
        } else {
            [unit(data[i]), unit(data[n + i]), unit(data[2 * n + i])]
        };
    }
    Ok(Decoded { width, height, rgb })
}
