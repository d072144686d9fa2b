//! AVS X image (`.x`, Advanced Visual Systems' "AVS image file format", the thesis's `x`): two
//! big-endian 32-bit words, width and height, then 8-bit A, R, G, B for each pixel, the top
//! row first. Its alpha channel follows the image output rule (opaque, or straight alpha after
//! `background none`: [`crate::framebuffer::output_pixel`]); the reader ignores alpha, as
//! `background` does for every format.

use std::io::{self, Write};

use super::{Bytes, Decoded, pixels, unit};
use crate::framebuffer::{Framebuffer, to_u8};

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    super::check_dims(fb, i32::MAX as usize, "AVS")?;
    w.write_all(&(fb.width as u32).to_be_bytes())?;
    w.write_all(&(fb.height as u32).to_be_bytes())?;
    let mut row = Vec::with_capacity(fb.width * 4);
    for line in fb.pixels.chunks(fb.width) {
        row.clear();
        row.extend(line.iter().flat_map(|p| {
            let [r, g, b, a] = fb.output_pixel(p).map(to_u8);
            [a, r, g, b]
        }));
        w.write_all(&row)?;
    }
    Ok(())
}

pub fn read(bytes: &[u8]) -> Result<Decoded, String> {
    let mut b = Bytes::new(bytes);
    let width = b.u32_be("the width")? as usize;
    let height = b.u32_be("the height")? as usize;
    let mut rgb = pixels(width, height, b.remaining(), (1, 4))?;
    let data = b.take(width * height * 4, "the pixels (4 bytes each)")?;
    for (p, q) in rgb.iter_mut().zip(data.chunks_exact(4)) {
        *p = [unit(q[1]), unit(q[2]), unit(q[3])];
    }
    Ok(Decoded { width, height, rgb })
}
