//! Reading Gmsh numbers: the same sequence of values is ASCII tokens in one file and binary
//! words (4-byte `int`, 8-byte `double`, `size_t` of the declared size, in the file's byte
//! order) in another. [`Msh`] hides the difference, so the section readers describe each
//! section once; it also bounds every count by what the rest of the file can hold.

use rayon::prelude::*;

use crate::error::ParseError;
use crate::formats::text::Cursor;

/// The reading position in a Gmsh file and how its numbers are stored.
pub(super) struct Msh<'a> {
    pub(super) c: Cursor<'a>,
    pub(super) binary: bool,
    /// Binary numbers in the other byte order than this machine's little-endian reading.
    pub(super) swap: bool,
    /// The size of a binary `size_t` (the data size of `$MeshFormat`).
    pub(super) size_t: usize,
}

impl<'a> Msh<'a> {
    pub(super) fn bytes(&mut self, n: usize, what: &str) -> Result<&'a [u8], ParseError> {
        self.c.raw(n, what)
    }

    fn word(&mut self, size: usize, what: &str) -> Result<u64, ParseError> {
        let b = self.bytes(size, what)?;
        Ok(word(b, self.swap))
    }

    /// `count` binary words of `size` bytes read at once and decoded on every core: reading
    /// them one at a time (a bounds check and a line count each) was a tenth of a binary load.
    pub(super) fn words(
        &mut self,
        count: usize,
        size: usize,
        what: &str,
    ) -> Result<Vec<u64>, ParseError> {
        self.records(count, size, what, word)
    }

    /// `count` records of `size` bytes read at once, each decoded by `decode` on every core.
    pub(super) fn records<T: Send>(
        &mut self,
        count: usize,
        size: usize,
        what: &str,
        decode: impl Fn(&[u8], bool) -> T + Sync + Send,
    ) -> Result<Vec<T>, ParseError> {
        let swap = self.swap;
        let b = self.bytes(count.saturating_mul(size), what)?;
        Ok(b.par_chunks_exact(size)
            .with_min_len(1 << 12)
            .map(|r| decode(r, swap))
            .collect())
    }

    /// The line the next token is on (ASCII; in binary data lines mean nothing, and the cursor
    /// must not skip bytes that look like blanks).
    pub(super) fn next_line_no(&mut self) -> usize {
        if !self.binary {
            self.c.skip_space();
        }
        self.c.line
    }

    /// A signed 32-bit int (binary) or an integer token (ASCII).
    pub(super) fn int(&mut self, what: &str) -> Result<i64, ParseError> {
        if self.binary {
            let b = self.bytes(4, what)?;
            Ok(int_word(b, self.swap))
        } else {
            self.c.int(what)
        }
    }

    /// A `size_t` (binary 4.1) or an integer token.
    pub(super) fn size(&mut self, what: &str) -> Result<u64, ParseError> {
        if self.binary {
            self.word(self.size_t, what)
        } else {
            let v = self.c.int(what)?;
            u64::try_from(v).map_err(|_| self.c.err(format!("expected {what} ≥ 0, found {v}")))
        }
    }

    pub(super) fn double(&mut self, what: &str) -> Result<f64, ParseError> {
        if self.binary {
            Ok(f64::from_bits(self.word(8, what)?))
        } else {
            self.c.float(what)
        }
    }

    /// A count that the rest of the file can hold at `min_bytes` per item.
    pub(super) fn bounded(
        &self,
        n: u64,
        min_bytes: usize,
        what: &str,
        line: usize,
    ) -> Result<usize, ParseError> {
        let left = (self.c.bytes.len() - self.c.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left + 1 {
            return Err(self.c.err_at(
                line,
                format!("{what} is {n}, more than the {left} bytes left in the file can hold"),
            ));
        }
        Ok(n as usize)
    }

    /// Moves past `$End<section>`.
    pub(super) fn end(&mut self, section: &str) -> Result<(), ParseError> {
        let want = format!("$End{section}");
        loop {
            let Some((t, _)) = self.c.token() else {
                return Err(self
                    .c
                    .err(format!("unexpected end of file: expected {want}")));
            };
            if t == want {
                return Ok(());
            }
            if t.starts_with('$') && !self.binary {
                return Err(self.c.err(format!("expected {want}, found '{t}'")));
            }
        }
    }
}

/// A binary word of 1 to 8 bytes, little-endian unless `swap`.
pub(super) fn word(b: &[u8], swap: bool) -> u64 {
    let mut w = [0u8; 8];
    if swap {
        for (i, x) in b.iter().rev().enumerate() {
            w[i] = *x;
        }
    } else {
        w[..b.len()].copy_from_slice(b);
    }
    u64::from_le_bytes(w)
}

/// A binary `int` (4 bytes, signed) widened as the word-at-a-time reader does.
pub(super) fn int_word(b: &[u8], swap: bool) -> i64 {
    int_of(word(b, swap))
}

/// The `int` a 4-byte word holds.
pub(super) fn int_of(w: u64) -> i64 {
    i64::from(w as u32 as i32)
}

pub(super) fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}
