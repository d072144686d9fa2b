//! BINARY data blocks: after the `@marker` line, `count × numbers × size` bytes of big-endian
//! IEEE/two's-complement data ("Standardworkstation", thesis B.2), optionally followed by one
//! newline.

use std::io::{self, BufRead, Write};

use super::ascii::BlockInfo;
use super::input::Input;
use crate::data::{DataType, Values};
use crate::error::ParseError;

/// Bytes converted per step; bounds the scratch buffer whatever the block size.
const CHUNK: usize = 1 << 20;

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
/// not finite (or, for doubles, beyond [`super::MAX_MAGNITUDE`]).
fn decode(bytes: &[u8], out: &mut Values) -> Result<(), usize> {
    match out {
        Values::U8(v) => v.extend_from_slice(bytes),
        Values::I16(v) => v.extend(
            bytes
                .chunks_exact(2)
                .map(|c| i16::from_be_bytes([c[0], c[1]])),
        ),
        Values::I32(v) => v.extend(
            bytes
                .chunks_exact(4)
                .map(|c| i32::from_be_bytes([c[0], c[1], c[2], c[3]])),
        ),
        Values::F32(v) => {
            let start = v.len();
            v.extend(
                bytes
                    .chunks_exact(4)
                    .map(|c| f32::from_be_bytes([c[0], c[1], c[2], c[3]])),
            );
            if let Some(i) = v[start..].iter().position(|x| !x.is_finite()) {
                return Err(i);
            }
        }
        Values::F64(v) => {
            let start = v.len();
            v.extend(
                bytes
                    .chunks_exact(8)
                    .map(|c| f64::from_be_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])),
            );
            if let Some(i) = v[start..]
                .iter()
                .position(|x| !x.is_finite() || x.abs() > super::MAX_MAGNITUDE)
            {
                return Err(i);
            }
        }
    }
    Ok(())
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
