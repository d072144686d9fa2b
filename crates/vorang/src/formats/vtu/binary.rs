//! The binary layouts of `format="binary"` and appended arrays: a header of 32- or 64-bit words
//! (the byte count, or the compressed-block table), then the data, as raw bytes or base64. This
//! phase turns a layout into the array's bytes, checking every length against the file before
//! use, and hands them to a [`Sink`]; the blocks themselves are inflated by [`super::compress`].
//! It is separate from the numbers ([`super::arrays`]) because it concerns only bytes, and its
//! bounds checks are what keep a hostile header from allocating more than the file can hold.

use base64::Engine as _;

use super::compress::{Compressor, decompress};
use super::sink::Sink;
use super::xml::Settings;

pub(super) fn b64() -> base64::engine::GeneralPurpose {
    base64::engine::GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        base64::engine::GeneralPurposeConfig::new()
            .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent)
            .with_decode_allow_trailing_bits(true),
    )
}

fn b64_decode(text: &[u8], what: &str) -> Result<Vec<u8>, String> {
    b64()
        .decode(text)
        .map_err(|e| format!("bad base64 in the {what}: {e}"))
}

/// Base64 characters for `n` bytes (padded).
fn b64_chars(n: usize) -> usize {
    n.div_ceil(3).saturating_mul(4)
}

/// The header (`header_bytes` long) and data of a base64 array: separately encoded if the
/// header's own encoding ends there (with padding, or on a 3-byte boundary), else one stream.
fn split_base64(text: &[u8], header_bytes: usize) -> Result<(Vec<u8>, Vec<u8>), String> {
    let c = b64_chars(header_bytes);
    if text.len() < c {
        return Err(format!(
            "the base64 text ends after {} characters, inside the {header_bytes}-byte header",
            text.len()
        ));
    }
    if header_bytes.is_multiple_of(3) || text[c - 1] == b'=' {
        let header = b64_decode(&text[..c], "header")?;
        let data = b64_decode(&text[c..], "data")?;
        Ok((header, data))
    } else {
        let mut all = b64_decode(text, "data")?;
        let data = all.split_off(header_bytes.min(all.len()));
        Ok((all, data))
    }
}

fn header_word(s: &Settings, h: &[u8], k: usize) -> u64 {
    let size = if s.header64 { 8 } else { 4 };
    let mut w = [0u8; 8];
    let chunk = &h[k * size..(k + 1) * size];
    if s.big_endian {
        for (i, b) in chunk.iter().rev().enumerate() {
            w[i] = *b;
        }
    } else {
        w[..size].copy_from_slice(chunk);
    }
    u64::from_le_bytes(w)
}

/// The compressed-block layout from a header.
struct Blocks {
    sizes: Vec<usize>,
    compressed: Vec<usize>,
}

impl Blocks {
    /// Whether the compressed blocks fit in the `available` bytes and each could expand to its
    /// declared size (zlib ≤ ~1032×, lz4 ≤ 255×): only then is room reserved up front.
    fn plausible(&self, c: Compressor, available: usize) -> bool {
        let ratio = match c {
            Compressor::Zlib => 1100,
            Compressor::Lz4 => 260,
            _ => return false,
        };
        self.compressed
            .iter()
            .fold(0usize, |a, &c| a.saturating_add(c))
            <= available
            && self
                .sizes
                .iter()
                .zip(&self.compressed)
                .all(|(&u, &c)| u <= c.saturating_mul(ratio).saturating_add(64))
    }
}

fn block_layout(s: &Settings, h: &[u8], nblocks: usize, want: usize) -> Result<Blocks, String> {
    let bs = header_word(s, h, 1);
    let last = header_word(s, h, 2);
    if nblocks > 0 && (bs == 0 || bs as usize > s.limit || last > bs) {
        return Err(format!(
            "compressed header: block size {bs} and last block size {last} are inconsistent"
        ));
    }
    let mut sizes = vec![bs as usize; nblocks];
    if let Some(l) = sizes.last_mut()
        && last != 0
    {
        *l = last as usize;
    }
    let total: usize = sizes.iter().fold(0usize, |a, &b| a.saturating_add(b));
    if total > s.limit {
        return Err(format!(
            "compressed header declares {total} bytes, more than this file can hold"
        ));
    }
    // Checked before decompressing anything: a wrong size is an error, not an allocation.
    if total < want {
        return Err(format!(
            "the compressed header declares {total} bytes, but the counts need {want}"
        ));
    }
    let compressed = (0..nblocks)
        .map(|k| header_word(s, h, 3 + k) as usize)
        .collect();
    Ok(Blocks { sizes, compressed })
}

fn header_size(s: &Settings) -> usize {
    if s.header64 { 8 } else { 4 }
}

/// Raw appended data starting at an array's offset (`at` = its byte offset in the file).
pub(super) fn binary_raw(
    s: &Settings,
    app: &[u8],
    at: usize,
    want: usize,
    sink: &mut Sink,
) -> Result<(), String> {
    let hs = header_size(s);
    let short = |what: &str, need: usize, have: usize| {
        format!("the file ends inside the {what}: {need} bytes needed from byte {at}, {have} there")
    };
    if app.len() < hs {
        return Err(short("header", hs, app.len()));
    }
    let first = header_word(s, app, 0);
    if s.compressor == Compressor::None {
        let n = usize::try_from(first).unwrap_or(usize::MAX);
        if n > app.len() - hs {
            return Err(short("data", n, app.len() - hs));
        }
        // Uncompressed raw data are converted straight from the file's bytes.
        sink.reserve(n);
        sink.push(&app[hs..hs + n]);
        return Ok(());
    }
    let nblocks = usize::try_from(first).unwrap_or(usize::MAX);
    let hbytes = nblocks
        .checked_add(3)
        .and_then(|n| n.checked_mul(hs))
        .filter(|&n| n <= app.len())
        .ok_or_else(|| {
            short(
                "compressed-block header",
                (nblocks.saturating_add(3)).saturating_mul(hs),
                app.len(),
            )
        })?;
    let layout = block_layout(s, &app[..hbytes], nblocks, want)?;
    if layout.plausible(s.compressor, app.len() - hbytes) {
        sink.reserve(layout.sizes.iter().sum());
    }
    inflate(s.compressor, &app[hbytes..], &layout, sink).map_err(|(k, pos, e)| match e {
        Failed::Short { need, have } => format!(
            "compressed block {} of {nblocks} at byte {} needs {need} bytes, but the file ends after {have}",
            k + 1,
            at + hbytes + pos,
        ),
        Failed::Bad(e) => format!(
            "compressed block {} of {nblocks} at byte {}: {e}",
            k + 1,
            at + hbytes + pos
        ),
    })
}

/// Why a compressed block could not be inflated.
enum Failed {
    /// It runs past the data: `need` bytes, `have` left.
    Short {
        need: usize,
        have: usize,
    },
    Bad(String),
}

/// Blocks inflated at a time, in parallel (VTK writes blocks of 32 KiB: a group holds a few
/// MiB).
const GROUP: usize = 64;

/// Inflates the blocks of `layout`, which follow one another in `data`, and hands them to the
/// sink in order. Groups of blocks are inflated in parallel; the error returned — with the
/// block's number and offset in `data` — is the one a serial pass meets first.
fn inflate(
    c: Compressor,
    data: &[u8],
    layout: &Blocks,
    sink: &mut Sink,
) -> Result<(), (usize, usize, Failed)> {
    use rayon::prelude::*;
    // Where each block lies, up to the first that runs past the data.
    let mut spans = Vec::with_capacity(layout.sizes.len());
    let mut short = None;
    let mut pos = 0usize;
    for (k, (&size, &csize)) in layout.sizes.iter().zip(&layout.compressed).enumerate() {
        if csize > data.len() - pos {
            let have = data.len() - pos;
            short = Some((k, pos, Failed::Short { need: csize, have }));
            break;
        }
        spans.push((k, pos, csize, size));
        pos += csize;
    }
    for group in spans.chunks(GROUP) {
        let blocks: Vec<Result<Vec<u8>, String>> = group
            .par_iter()
            .map(|&(_, pos, csize, size)| {
                let mut out = Vec::new();
                decompress(c, &data[pos..pos + csize], size, &mut out).map(|()| out)
            })
            .collect();
        for (&(k, pos, _, _), block) in group.iter().zip(blocks) {
            sink.push(&block.map_err(|e| (k, pos, Failed::Bad(e)))?);
        }
    }
    short.map_or(Ok(()), Err)
}

/// Base64 text (whitespace removed) of one array.
pub(super) fn binary_base64(
    s: &Settings,
    text: &[u8],
    want: usize,
    sink: &mut Sink,
) -> Result<(), String> {
    let hs = header_size(s);
    if s.compressor == Compressor::None {
        let (h, mut data) = split_base64(text, hs)?;
        if h.len() < hs {
            return Err("the base64 header is too short".into());
        }
        let n = usize::try_from(header_word(s, &h, 0)).unwrap_or(usize::MAX);
        if n > data.len() {
            return Err(format!(
                "the header says {n} bytes, but the base64 data hold only {}",
                data.len()
            ));
        }
        data.truncate(n);
        sink.reserve(n);
        sink.push(&data);
        return Ok(());
    }
    // The first header word (the number of blocks) decides the header's length.
    let c = b64_chars(hs);
    if text.len() < c {
        return Err("the base64 text is too short for a compressed-block header".into());
    }
    let first = b64_decode(&text[..c], "header")?;
    if first.len() < hs {
        return Err("the base64 header is too short".into());
    }
    let nblocks = usize::try_from(header_word(s, &first, 0)).unwrap_or(usize::MAX);
    let hbytes = nblocks
        .checked_add(3)
        .and_then(|n| n.checked_mul(hs))
        .filter(|&n| b64_chars(n) <= text.len())
        .ok_or_else(|| {
            format!(
                "the header declares {nblocks} compressed blocks, more than the base64 text holds"
            )
        })?;
    let (h, data) = split_base64(text, hbytes)?;
    if h.len() < hbytes {
        return Err("the base64 header is too short".into());
    }
    let layout = block_layout(s, &h, nblocks, want)?;
    if layout.plausible(s.compressor, data.len()) {
        sink.reserve(layout.sizes.iter().sum());
    }
    inflate(s.compressor, &data, &layout, sink).map_err(|(k, _, e)| match e {
        Failed::Short { need, have } => format!(
            "compressed block {} of {nblocks} needs {need} bytes, but the decoded data end after {have}",
            k + 1,
        ),
        Failed::Bad(e) => format!("compressed block {} of {nblocks}: {e}", k + 1),
    })
}

#[cfg(test)]
mod tests {
    use super::super::sink::Sink;
    use super::super::xml::NumType;
    use super::*;

    #[test]
    fn absurd_block_counts_are_errors() {
        // Found by fuzzing: a block count near 2^64 in a base64 header.
        assert_eq!(b64_chars(usize::MAX), usize::MAX);
        let text = b64().encode([0xffu8; 8]);
        let s = Settings {
            name: "x.vtu",
            file: &[],
            big_endian: false,
            header64: true,
            compressor: Compressor::Zlib,
            version: (1, 0),
            appended: None,
            offsets: Vec::new(),
            limit: 1 << 20,
        };
        let mut sink = Sink::new(NumType::F64, false, 8);
        assert!(binary_base64(&s, text.as_bytes(), 8, &mut sink).is_err());
    }

    #[test]
    fn header_and_data_in_one_or_two_base64_streams() {
        let header = 8u32.to_le_bytes();
        let data = [1u8, 2, 3, 4, 5, 6, 7, 8];
        let two = [b64().encode(header), b64().encode(data)].concat();
        let one = b64().encode([&header[..], &data[..]].concat());
        for text in [two, one] {
            let (h, d) = split_base64(text.as_bytes(), 4).unwrap();
            assert_eq!(h, header);
            assert_eq!(d, data);
        }
    }
}
