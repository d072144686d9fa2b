//! Image settings: `imagesize`, `output`, `set_nr`, `background`, `movie` (thesis A.1 „Bildangaben“).

use super::{Call, CommandInfo};
use crate::script::Context;
use vorang::framebuffer::Background;

pub const IMAGESIZE: CommandInfo = CommandInfo {
    name: "imagesize",
    usage: "width height",
    summary: "size of the images in pixels",
    details: "Default 512 512.",
    run: |s: &mut Context, c: &Call| {
        c.expect(2..=2)?;
        let (w, h) = (c.count(0, "width")?, c.count(1, "height")?);
        s.session.set_image_size(w, h)?;
        Ok(String::new())
    },
};

pub const OUTPUT: CommandInfo = CommandInfo {
    name: "output",
    usage: "base.format",
    summary: "base name and format of the images: 'output img.png' writes img.0001.png, img.0002.png …",
    details: "The format follows the extension: tiff/tif (default: vorang.tiff), png, bmp, tga, ppm/pnm, pgm, pam, jpg/jpeg, gif, ico, qoi, webp, hdr, exr, pfm (float RGB), rgb/sgi/rgba (SGI), and from the thesis's list pbm and xbm (1-bit: white where the luminance is at least 0.5), xwd, ras, pcx, eps, ps, pict, iff (Amiga ILBM), x (AVS), viff (Khoros) and rle (Utah RLE, the thesis's rlc) — docs/formats.md lists them all. 8-bit formats clip to [0, 1]; exr, pfm and hdr keep the floats. Missing folders are created. A different base name restarts the numbers at 1 (use set_nr after output to start elsewhere); the same base again, also in another format, keeps counting.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=1)?;
        s.session.set_output(c.path(0))?;
        Ok(String::new())
    },
};

pub const SET_NR: CommandInfo = CommandInfo {
    name: "set_nr",
    usage: "number",
    summary: "the number the next image gets in its file name",
    details: "The first image is number 1 (base.0001.ext); every render counts up.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=1)?;
        s.session.set_number(c.count(0, "number")?)?;
        Ok(String::new())
    },
};

pub const BACKGROUND: CommandInfo = CommandInfo {
    name: "background",
    usage: "file|clear|none|r g b",
    summary: "an image under the volume (resampled to the image size), 'clear' for uniform white, 'none' for a transparent image, or a uniform colour",
    details: "Default: uniform white. The image may be in any format 'output' writes except eps and ps (reading PostScript needs an interpreter); its 8-bit values count as intensities 0…1, pfm, exr and hdr values as they are. A colour (e.g. 'background 0 0 0') is an extension of the thesis's command. Image files are opaque (what the framebuffer shows, composited over the background); 'none' means no background light and writes straight alpha (the volume's opacity) where the format has alpha — light emitted without absorption cannot be represented that way.",
    run: |s: &mut Context, c: &Call| {
        if c.args().len() == 3 {
            let rgb = c.numbers(0, ["r", "g", "b"])?;
            s.session.set_background(Background::Color(rgb))?;
            return Ok(String::new());
        }
        c.expect(1..=1)?;
        match c.args()[0].as_str() {
            "clear" => s.session.set_background(Background::default())?,
            "none" => s.session.set_background(Background::None)?,
            _ => s.session.load_background(&c.path(0))?,
        }
        Ok(String::new())
    },
};

pub const MOVIE: CommandInfo = CommandInfo {
    name: "movie",
    usage: "file ?fps? | close",
    summary: "collect the following renders as the frames of an animation: 'movie spin.gif 15' … render_btf … 'movie close' writes spin.gif",
    details: "While a movie is open, each render adds a frame (with the legend, if on) instead of writing a numbered image; the frames wait in a hidden folder .NAME.frames next to the movie. Formats by extension: gif (256 colours per frame), apng or png (animated PNG, full colour) written by VoRANG; mp4, webm, mkv, mov through the ffmpeg program, which must be on the PATH. Default 10 frames per second; the movie loops. A new 'movie' closes the open one; so does the end of the session.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=2)?;
        if c.args()[0] == "close" && c.args().len() == 1 {
            return match s.session.close_movie()? {
                Some((path, note)) => {
                    s.report([note]);
                    Ok(path.display().to_string())
                }
                None => Err("movie close: no movie is open".into()),
            };
        }
        let fps = if c.args().len() == 2 {
            c.number(1, "fps")?
        } else {
            10.0
        };
        let notes = s.session.open_movie(&c.path(0), fps)?;
        s.report(notes);
        Ok(String::new())
    },
};
