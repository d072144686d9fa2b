//! Decoded bytes to numbers as they arrive: the [`Sink`] both the array decoding
//! ([`super::arrays`]) and the binary layer ([`super::binary`], block by block for compressed
//! data) write into, so that neither needs the other and a large array never exists twice.

use super::xml::NumType;
use crate::formats::ArrayValues;

/// Out-of-range indices with their positions (the first few), for messages.
pub(super) type Outside = Vec<(usize, i64)>;

/// How many out-of-range indices [`decode_indices`] keeps for messages.
pub(super) const MAX_OUTSIDE: usize = 16;

/// 32-bit index output of a [`Sink`].
pub(super) struct IndexOut {
    pub(super) v: Vec<u32>,
    /// Indices must be below this.
    pub(super) limit: u64,
    pub(super) outside: Outside,
}

/// Turns decoded bytes into values as they arrive (block by block for compressed data), so a
/// large array never exists twice — once as bytes, once as numbers.
pub(super) struct Sink {
    pub(super) ty: NumType,
    pub(super) big: bool,
    /// Bytes wanted; what arrives beyond is counted, not kept.
    pub(super) want: usize,
    pub(super) seen: usize,
    pub(super) carry: Vec<u8>,
    pub(super) out: ArrayValues,
    /// Set for the connectivity: 32-bit indices instead of `out`.
    pub(super) index: Option<IndexOut>,
    pub(super) error: Option<String>,
}

impl Sink {
    pub(super) fn new(ty: NumType, big: bool, want: usize) -> Sink {
        let out = match ty {
            NumType::F32 => ArrayValues::F32(Vec::new()),
            NumType::F64 => ArrayValues::F64(Vec::new()),
            _ => ArrayValues::Int(Vec::new()),
        };
        Sink {
            ty,
            big,
            want,
            seen: 0,
            carry: Vec::new(),
            out,
            index: None,
            error: None,
        }
    }

    /// Makes room for `bytes` of data — called once the file is known to hold them (the
    /// counts alone could ask for anything).
    pub(super) fn reserve(&mut self, bytes: usize) {
        let n = bytes.min(self.want) / self.ty.size();
        if let Some(idx) = &mut self.index {
            idx.v.reserve_exact(n);
            return;
        }
        match &mut self.out {
            ArrayValues::F32(v) => v.reserve_exact(n),
            ArrayValues::F64(v) => v.reserve_exact(n),
            ArrayValues::Int(v) => v.reserve_exact(n),
        }
    }

    pub(super) fn push(&mut self, bytes: &[u8]) {
        let keep = bytes.len().min(self.want.saturating_sub(self.seen));
        self.seen = self.seen.saturating_add(bytes.len());
        let mut bytes = &bytes[..keep];
        let size = self.ty.size();
        if !self.carry.is_empty() {
            let take = (size - self.carry.len()).min(bytes.len());
            self.carry.extend_from_slice(&bytes[..take]);
            bytes = &bytes[take..];
            if self.carry.len() == size {
                let c = std::mem::take(&mut self.carry);
                self.convert(&c);
            }
        }
        let whole = bytes.len() / size * size;
        self.convert(&bytes[..whole]);
        self.carry.extend_from_slice(&bytes[whole..]);
    }

    fn convert(&mut self, data: &[u8]) {
        if let Some(idx) = &mut self.index {
            convert_indices(data, self.ty, self.big, idx);
            return;
        }
        if let Err(e) = convert_into(data, self.ty, self.big, &mut self.out) {
            self.error.get_or_insert(e);
        }
    }

    pub(super) fn finish(self) -> Result<ArrayValues, String> {
        match self.error {
            Some(e) => Err(e),
            None => Ok(self.out),
        }
    }
}

/// Appends the integers in `data` to `out` as 32-bit indices (see [`decode_indices`]).
fn convert_indices(data: &[u8], ty: NumType, big: bool, out: &mut IndexOut) {
    let IndexOut { v, limit, outside } = out;
    let limit = *limit;
    let first = v.len();
    let mut check = |i: usize, x: i64| -> u32 {
        if (0..limit as i64).contains(&x) {
            x as u32
        } else {
            if outside.len() < MAX_OUTSIDE {
                outside.push((first + i, x));
            }
            u32::MAX
        }
    };
    let size = ty.size();
    let chunks = data.chunks_exact(size);
    match (ty, big) {
        (NumType::I64, false) => v.extend(chunks.enumerate().map(|(i, c)| {
            check(
                i,
                i64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]),
            )
        })),
        (NumType::I32, false) => v.extend(
            chunks
                .enumerate()
                .map(|(i, c)| check(i, i64::from(i32::from_le_bytes([c[0], c[1], c[2], c[3]])))),
        ),
        _ => {
            let mut tmp = ArrayValues::Int(Vec::with_capacity(data.len() / size));
            let result = convert_into(data, ty, big, &mut tmp);
            if let (Ok(()), ArrayValues::Int(t)) = (result, tmp) {
                v.extend(t.into_iter().enumerate().map(|(i, x)| check(i, x)));
            } else {
                // A UInt64 beyond i64: out of range like any other.
                let n = data.len() / size;
                v.extend((0..n).map(|i| check(i, -1)));
            }
        }
    }
}

fn convert_into(data: &[u8], ty: NumType, big: bool, out: &mut ArrayValues) -> Result<(), String> {
    let size = ty.size();
    // The common cases, little-endian and whole numbers of elements, in tight loops that the
    // compiler vectorises (large connectivity arrays spend most of their reading time here).
    if !big {
        let chunks = data.chunks_exact(size);
        let four = |c: &[u8]| [c[0], c[1], c[2], c[3]];
        let eight = |c: &[u8]| [c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]];
        match (ty, &mut *out) {
            (NumType::F32, ArrayValues::F32(v)) => {
                v.extend(chunks.map(|c| f32::from_le_bytes(four(c))));
                return Ok(());
            }
            (NumType::F64, ArrayValues::F64(v)) => {
                v.extend(chunks.map(|c| f64::from_le_bytes(eight(c))));
                return Ok(());
            }
            (NumType::I64, ArrayValues::Int(v)) => {
                v.extend(chunks.map(|c| i64::from_le_bytes(eight(c))));
                return Ok(());
            }
            (NumType::I32, ArrayValues::Int(v)) => {
                v.extend(chunks.map(|c| i64::from(i32::from_le_bytes(four(c)))));
                return Ok(());
            }
            (NumType::U8, ArrayValues::Int(v)) => {
                v.extend(data.iter().map(|&b| i64::from(b)));
                return Ok(());
            }
            _ => {}
        }
    }
    let word = |chunk: &[u8]| -> [u8; 8] {
        let mut w = [0u8; 8];
        if big {
            for (k, b) in chunk.iter().rev().enumerate() {
                w[k] = *b;
            }
        } else {
            w[..chunk.len()].copy_from_slice(chunk);
        }
        w
    };
    let chunks = data.chunks_exact(size);
    match out {
        ArrayValues::F32(v) => v.extend(chunks.map(|c| {
            let w = word(c);
            f32::from_le_bytes([w[0], w[1], w[2], w[3]])
        })),
        ArrayValues::F64(v) => v.extend(chunks.map(|c| f64::from_le_bytes(word(c)))),
        ArrayValues::Int(out) => {
            for c in chunks {
                let w = word(c);
                let v = match ty {
                    NumType::I8 => i64::from(w[0] as i8),
                    NumType::U8 => i64::from(w[0]),
                    NumType::I16 => i64::from(i16::from_le_bytes([w[0], w[1]])),
                    NumType::U16 => i64::from(u16::from_le_bytes([w[0], w[1]])),
                    NumType::I32 => i64::from(i32::from_le_bytes([w[0], w[1], w[2], w[3]])),
                    NumType::U32 => i64::from(u32::from_le_bytes([w[0], w[1], w[2], w[3]])),
                    NumType::I64 => i64::from_le_bytes(w),
                    _ => {
                        let u = u64::from_le_bytes(w);
                        i64::try_from(u).map_err(|_| format!("UInt64 value {u} is too large"))?
                    }
                };
                out.push(v);
            }
        }
    }
    Ok(())
}
