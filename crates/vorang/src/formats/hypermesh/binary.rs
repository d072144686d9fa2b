//! BINARY data blocks: after the `@marker` line, `count × numbers × size` bytes of big-endian
//! IEEE/two's-complement data ("Standardworkstation", thesis B.2), optionally followed by one
//! newline.

use std::io::{self, BufRead, Write};

use rayon::prelude::*;

use super::ascii::BlockInfo;
use super::input::Input;
use crate::data::{DataType, Values};
use crate::error::ParseError;

/// Bytes converted per step; bounds the scratch buffer whatever the block size.
const CHUNK: usize = 1 << 22;

/// Reads one block of `count` elements of type `ty`.
pub fn read_block<R: BufRead>(
    input: &mut Input<R>,
    info: &BlockInfo,
    ty: DataType,
    count: usize,
) -> Result<Values, ParseError> {
    let size = ty.scalar.number_size();
    let numbers = (count as u64).saturating_mul(ty.numbers() as u64);
    let bytes = numbers.saturating_mul(size as u64);
    let truncated = |found: u64| {
        ParseError::new(
            info.file,
            info.marker_line,
            format!(
                "block @{} ({}) is truncated: expected {bytes} bytes ({count} × {ty}, {} = {count}), found {found}",
                info.marker, info.what, info.count_keyword
            ),
        )
    };
    if let Some(rem) = input.remaining()
        && bytes > rem
    {
        return Err(truncated(rem));
    }
    let numbers = numbers as usize;
    let bound = input.remaining().map_or(CHUNK, |r| r as usize / size);
    let mut values = Values::with_capacity(ty.scalar, numbers.min(bound));
    let mut scratch = Vec::with_capacity(CHUNK.min(bytes as usize));
    let mut done: u64 = 0;
    while done < bytes {
        let want = ((bytes - done) as usize).min(CHUNK);
        scratch.clear();
        let got = input.read_bytes(want, &mut scratch).map_err(|e| {
            ParseError::new(info.file, info.marker_line, format!("read error: {e}"))
        })?;
        if got < want {
            return Err(truncated(done + got as u64));
        }
        input.count_lines_in(&scratch);
        let first_number = (done / size as u64) as usize;
        decode(&scratch, &mut values).map_err(|bad| {
            let element = (first_number + bad) / ty.numbers().max(1) + 1;
            ParseError::new(
                info.file,
                info.marker_line,
                format!(
                    "block @{} ({}): element {element} holds a non-finite value (NaN or infinity) or one beyond ±{:e}",
                    info.marker,
                    info.what,
                    super::MAX_MAGNITUDE
                ),
            )
        })?;
        done += got as u64;
    }
    input
        .skip_newline()
        .map_err(|e| ParseError::new(info.file, info.marker_line, format!("read error: {e}")))?;
    Ok(values)
}

/// Appends the big-endian numbers in `bytes` to `out`; `Err(i)` if number `i` of this chunk is
/// not finite (or, for doubles, beyond [`super::MAX_MAGNITUDE`]). In parallel: the chunks are
/// large enough to share out, and decoding is what a BINARY file's loading spends its time on
/// besides building the mesh.
fn decode(bytes: &[u8], out: &mut Values) -> Result<(), usize> {
    match out {
        Values::U8(v) => v.extend_from_slice(bytes),
        Values::I16(v) => decode_into(bytes, v, i16::from_be_bytes),
        Values::I32(v) => decode_into(bytes, v, i32::from_be_bytes),
        Values::F32(v) => {
            let start = v.len();
            decode_into(bytes, v, f32::from_be_bytes);
            if let Some(i) = v[start..]
                .par_iter()
                .with_min_len(NUMBERS_PER_TASK)
                .position_first(|x| !x.is_finite())
            {
                return Err(i);
            }
        }
        Values::F64(v) => {
            let start = v.len();
            decode_into(bytes, v, f64::from_be_bytes);
            if let Some(i) = v[start..]
                .par_iter()
                .with_min_len(NUMBERS_PER_TASK)
                .position_first(|x| !x.is_finite() || x.abs() > super::MAX_MAGNITUDE)
            {
                return Err(i);
            }
        }
    }
    Ok(())
}

/// Numbers per parallel task of [`decode`].
const NUMBERS_PER_TASK: usize = 1 << 15;

/// Appends the numbers of `S` bytes each in `bytes` to `v`, converted by `from_be`.
fn decode_into<T: Copy + Default + Send, const S: usize>(
    bytes: &[u8],
    v: &mut Vec<T>,
    from_be: fn([u8; S]) -> T,
) {
    let start = v.len();
    v.resize(start + bytes.len() / S, T::default());
    v[start..]
        .par_chunks_mut(NUMBERS_PER_TASK)
        .zip(bytes.par_chunks(NUMBERS_PER_TASK * S))
        .for_each(|(out, bytes)| {
            for (x, b) in out.iter_mut().zip(bytes.chunks_exact(S)) {
                let mut word = [0u8; S];
                word.copy_from_slice(b);
                *x = from_be(word);
            }
        });
}

/// Writes all values big-endian.
pub fn write_values(out: &mut impl Write, values: &Values) -> io::Result<()> {
    let mut buf: Vec<u8> = Vec::with_capacity(CHUNK);
    macro_rules! emit {
        ($v:expr, $n:expr) => {
            for chunk in $v.chunks(CHUNK / $n) {
                buf.clear();
                for x in chunk {
                    buf.extend_from_slice(&x.to_be_bytes());
                }
                out.write_all(&buf)?;
            }
        };
    }
    match values {
        Values::U8(v) => out.write_all(v)?,
        Values::I16(v) => emit!(v, 2),
        Values::I32(v) => emit!(v, 4),
        Values::F32(v) => emit!(v, 4),
        Values::F64(v) => emit!(v, 8),
    }
    Ok(())
}
