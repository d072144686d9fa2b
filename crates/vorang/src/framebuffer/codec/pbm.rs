//! Portable bitmap, binary `P4` (Netpbm's pbm(5)): 1 bit per pixel, **1 = black**, each row
//! packed from the most significant bit and padded to whole bytes. The picture becomes black
//! and white by the luminance threshold of [`super::is_white`]. Reading (for `background`) goes
//! through the `image` crate, which reads all Netpbm formats.

use std::io::{self, Write};

use super::is_white;
use crate::framebuffer::Framebuffer;

pub fn write(fb: &Framebuffer, w: &mut impl Write) -> io::Result<()> {
    write!(w, "P4\n{} {}\n", fb.width, fb.height)?;
    let mut row = vec![0u8; fb.width.div_ceil(8)];
    for line in fb.pixels.chunks(fb.width.max(1)) {
        row.fill(0);
        for (x, p) in line.iter().enumerate() {
            if !is_white(p) {
                row[x / 8] |= 0x80 >> (x % 8);
            }
        }
        w.write_all(&row)?;
    }
    Ok(())
}
