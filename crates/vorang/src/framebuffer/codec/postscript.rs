//! PostScript (`.ps`) and Encapsulated PostScript (`.eps`, Adobe's "PostScript Language
//! Reference", 3rd ed., and "Encapsulated PostScript File Format Specification" 3.0): the
//! picture as one 8-bit RGB `colorimage` with hexadecimal data (LanguageLevel 2, or Level 1 with
//! the colour extensions), one pixel per point (1/72 inch), the top row first. The `.ps` file
//! sets its page to the image's size (`setpagedevice`) so that it prints without margins; the
//! `.eps` file has only its bounding box, for placing in a document. There is no reader: reading
//! PostScript needs an interpreter (Ghostscript).

use std::io::{self, Write};

use super::rows8;
use crate::framebuffer::Framebuffer;

pub fn write(fb: &Framebuffer, w: &mut impl Write, encapsulated: bool) -> io::Result<()> {
    let (width, height) = (fb.width, fb.height);
    if encapsulated {
        writeln!(w, "%!PS-Adobe-3.0 EPSF-3.0")?;
    } else {
        writeln!(w, "%!PS-Adobe-3.0")?;
    }
    writeln!(w, "%%Creator: VoRANG")?;
    writeln!(w, "%%BoundingBox: 0 0 {width} {height}")?;
    writeln!(w, "%%LanguageLevel: 2")?;
    if !encapsulated {
        writeln!(w, "%%Pages: 1")?;
    }
    writeln!(w, "%%EndComments")?;
    if !encapsulated {
        writeln!(w, "%%Page: 1 1")?;
        writeln!(w, "<< /PageSize [{width} {height}] >> setpagedevice")?;
    }
    writeln!(w, "gsave")?;
    writeln!(w, "/row {} string def", width * 3)?;
    writeln!(w, "{width} {height} scale")?;
    // The unit square maps to the image: the matrix puts row 0 at the top.
    writeln!(
        w,
        "{width} {height} 8 [{width} 0 0 -{height} 0 {height}] {{currentfile row readhexstring pop}} false 3 colorimage"
    )?;
    const HEX: &[u8; 16] = b"0123456789abcdef";
    let mut line = Vec::with_capacity(80);
    for row in rows8(fb) {
        for byte in row.iter().flatten() {
            line.push(HEX[(byte >> 4) as usize]);
            line.push(HEX[(byte & 15) as usize]);
            if line.len() >= 72 {
                line.push(b'\n');
                w.write_all(&line)?;
                line.clear();
            }
        }
    }
    if !line.is_empty() {
        line.push(b'\n');
        w.write_all(&line)?;
    }
    writeln!(w, "grestore")?;
    writeln!(w, "showpage")?;
    writeln!(w, "%%EOF")?;
    Ok(())
}
