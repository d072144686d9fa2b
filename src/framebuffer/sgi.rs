//! SGI image files (`.rgb`, the thesis's example format; Paul Haeberli's specification):
//! a 512-byte big-endian header, then uncompressed channel planes, each from the bottom row up.

use std::io::{self, Write};

use super::{Framebuffer, to_u8};

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
