//! Decompression of one compressed block (zlib, lz4 or lzma/xz), as VTK's
//! `vtk*DataCompressor`s write them. Each block is inflated into a buffer of exactly the size the
//! header declares, and a block that claims more than its codec could expand to is refused
//! before anything is allocated. The codecs are kept out of the layout code ([`super::binary`])
//! because each has its own failure modes and library quirks (see [`lzma`]), and a corrupt block
//! must give an error, never a panic or an unbounded allocation.

/// The `compressor` of `<VTKFile>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Compressor {
    None,
    Zlib,
    Lz4,
    Lzma,
}

/// A writer that refuses to grow past a limit (bounds what a corrupt stream can produce).
struct Limited<'a> {
    out: &'a mut Vec<u8>,
    left: usize,
}

impl std::io::Write for Limited<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if buf.len() > self.left {
            return Err(std::io::Error::other(
                "decompresses to more bytes than declared",
            ));
        }
        self.left -= buf.len();
        self.out.extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Decompresses one block of `size` bytes, appending to `out`.
pub(super) fn decompress(
    c: Compressor,
    src: &[u8],
    size: usize,
    out: &mut Vec<u8>,
) -> Result<(), String> {
    let start = out.len();
    // Neither zlib nor lz4 can expand by more than about 1032× and 255×: a block that claims
    // more is corrupt, and refusing it here keeps allocation proportional to the input.
    let ratio = match c {
        Compressor::Zlib => Some(1100),
        Compressor::Lz4 => Some(260),
        _ => None,
    };
    if let Some(r) = ratio
        && size > src.len().saturating_mul(r).saturating_add(64)
    {
        return Err(format!(
            "{} compressed bytes cannot hold the {size} bytes the header declares",
            src.len()
        ));
    }
    match c {
        Compressor::None => out.extend_from_slice(src),
        Compressor::Zlib => zlib(src, size, out)?,
        Compressor::Lz4 => lz4(src, size, out)?,
        Compressor::Lzma => lzma(src, size, out)?,
    }
    let n = out.len() - start;
    if n != size {
        return Err(format!(
            "decompresses to {n} bytes, but the header declares {size}"
        ));
    }
    Ok(())
}

/// One zlib stream that must end exactly after `size` bytes.
fn zlib(src: &[u8], size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    let mut d = flate2::Decompress::new(true);
    out.reserve(size);
    let mut buf = vec![0u8; size];
    let status = d
        .decompress(src, &mut buf, flate2::FlushDecompress::Finish)
        .map_err(|e| format!("corrupt zlib data: {e}"))?;
    let n = d.total_out() as usize;
    if status != flate2::Status::StreamEnd {
        return Err(if n == size {
            format!("the zlib stream holds more than the {size} bytes declared")
        } else {
            format!("the zlib stream ends early: {n} of {size} bytes")
        });
    }
    out.extend_from_slice(&buf[..n]);
    Ok(())
}

/// One lz4 block (no frame), at most `size` bytes.
fn lz4(src: &[u8], size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    let mut buf = vec![0u8; size];
    let n = lz4_flex::block::decompress_into(src, &mut buf)
        .map_err(|e| format!("corrupt lz4 data: {e}"))?;
    out.extend_from_slice(&buf[..n]);
    Ok(())
}

/// One xz stream, cut off beyond `size` bytes.
fn lzma(src: &[u8], size: usize, out: &mut Vec<u8>) -> Result<(), String> {
    let mut input = src;
    let mut w = Limited { out, left: size };
    // lzma-rs 0.3 overflows an addition on a corrupt stream footer (backward size
    // 2^32 − 1; found by fuzzing): a panic in builds with overflow checks, a wrapped
    // value and an error without. A corrupt block is an error here either way.
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        lzma_rs::xz_decompress(&mut input, &mut w)
    }));
    match result {
        Ok(r) => r.map_err(|e| format!("corrupt lzma (xz) data: {e}")),
        Err(_) => Err("corrupt lzma (xz) data: the stream footer is invalid".into()),
    }
}
