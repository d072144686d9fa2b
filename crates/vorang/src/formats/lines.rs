//! Rows of an ASCII section parsed on every core. Gmsh's node and element sections are a stream
//! of tokens, read one at a time by [`Cursor`]; in files as Gmsh and meshio write them, each row
//! is one line. So the next `n` lines are found (one pass for line ends), cut into pieces of
//! about 64 KiB, and each piece's lines are parsed by itself; the rows come back in file order.
//!
//! This is only a faster way to the same result: a row function accepts a line only if the
//! token reader would read exactly those numbers from it, so anything unusual (a blank line, a
//! row split over lines, a number in a rarer spelling, a bad token) makes the whole fast path
//! decline, and the caller reads the section token by token as before — with its messages.

use rayon::prelude::*;

use super::text::{Cursor, count_lines};

#[cfg(test)]
thread_local! {
    /// Set by tests to read this thread's files token by token, the reference for the rows.
    pub static TOKENS_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The bytes one piece covers: several pieces per core, each worth far more than handing it out.
const PIECE: usize = 64 << 10;

/// The `n` rows after the cursor's current line, as pieces of (first byte, rows), with the end
/// of the last row; `None` if the rest of the current line is not blank or the file ends first.
fn pieces(c: &Cursor, n: usize) -> Option<(Vec<(usize, usize)>, usize)> {
    #[cfg(test)]
    if TOKENS_ONLY.with(std::cell::Cell::get) {
        return None;
    }
    let bytes = c.bytes;
    let rest = &bytes[c.pos.min(bytes.len())..];
    let eol = memchr::memchr(b'\n', rest)?;
    if !rest[..eol].iter().all(u8::is_ascii_whitespace) || n == 0 {
        return None;
    }
    let first = c.pos + eol + 1;
    // Line ends are counted a block at a time (a loop the compiler vectorises), and found one
    // by one only in the block where the n-th row ends.
    let mut pieces = Vec::new();
    let (mut start, mut rows) = (first, 0);
    let end = loop {
        let block = &bytes[start..(start + PIECE).min(bytes.len())];
        let ends = count_lines(block);
        if rows + ends >= n {
            let k = memchr::memchr_iter(b'\n', block).nth(n - rows - 1)?;
            pieces.push((start, n - rows));
            break start + k;
        }
        if start + block.len() == bytes.len() {
            // The last row may end the file without a line end.
            if rows + ends + 1 == n && block.last() != Some(&b'\n') {
                pieces.push((start, n - rows));
                break bytes.len();
            }
            return None;
        }
        if ends > 0 {
            let last = memchr::memrchr(b'\n', block)?;
            pieces.push((start, ends));
            rows += ends;
            start += last + 1;
        } else {
            // A line longer than a piece: the next block goes on from the same start.
            let more = memchr::memchr(b'\n', &bytes[start..])?;
            if rows + 1 == n {
                pieces.push((start, n - rows));
                break start + more;
            }
            pieces.push((start, 1));
            rows += 1;
            start += more + 1;
        }
    };
    Some((pieces, end))
}

/// Moves the cursor past `n` rows ending at `end`, to where reading them token by token stops:
/// after the last row's last token, on its line.
fn finish(c: &mut Cursor, n: usize, end: usize) {
    let bytes = c.bytes;
    let last_start = memchr::memrchr(b'\n', &bytes[c.pos..end]).map_or(c.pos, |i| c.pos + i + 1);
    c.pos = bytes[last_start..end]
        .iter()
        .rposition(|b| !b.is_ascii_whitespace())
        .map_or(last_start, |i| last_start + i + 1);
    c.line += n;
}

/// Calls `each` on the `count` lines from `start` (the last may end at `text`'s end).
fn each_line(text: &[u8], start: usize, count: usize, mut each: impl FnMut(&[u8]) -> bool) -> bool {
    let mut pos = start;
    for _ in 0..count {
        let end = memchr::memchr(b'\n', &text[pos..]).map_or(text.len(), |i| pos + i);
        if !each(&text[pos..end]) {
            return false;
        }
        pos = end + 1;
    }
    true
}

/// Parses the `n` lines after the cursor's current line, `width` values each, by `row` (which
/// fills its row's values and returns false to decline). The rest of the current line must be
/// blank. On success the cursor stands where reading the same rows token by token would leave
/// it (after the last row's last token) and the values are returned in file order; otherwise the
/// cursor has not moved. Every piece writes its rows straight into the result.
pub fn parse_rows<T, F>(c: &mut Cursor, n: usize, width: usize, row: F) -> Option<Vec<T>>
where
    T: Copy + Default + Send,
    F: Fn(&[u8], &mut [T]) -> bool + Sync,
{
    let (pieces, end) = pieces(c, n)?;
    let mut all = vec![T::default(); n.checked_mul(width)?];
    let mut slots = Vec::with_capacity(pieces.len());
    let mut rest = &mut all[..];
    for &(start, count) in &pieces {
        let (mine, tail) = rest.split_at_mut(count * width);
        slots.push((start, count, mine));
        rest = tail;
    }
    let text = &c.bytes[..end];
    let ok = slots.into_par_iter().all(|(start, count, out)| {
        let mut rows = out.chunks_exact_mut(width.max(1));
        each_line(text, start, count, |line| {
            rows.next().is_some_and(|r| row(line, r))
        })
    });
    if !ok {
        return None;
    }
    finish(c, n, end);
    Some(all)
}

/// As [`parse_rows`] for rows of varying length: `row` pushes a row's values (and whatever it
/// needs to tell the rows apart) onto the piece's vector.
pub fn parse_rows_with<T, F>(c: &mut Cursor, n: usize, row: F) -> Option<Vec<T>>
where
    T: Send,
    F: Fn(&[u8], &mut Vec<T>) -> bool + Sync,
{
    let (pieces, end) = pieces(c, n)?;
    let text = &c.bytes[..end];
    let parsed: Option<Vec<Vec<T>>> = pieces
        .par_iter()
        .map(|&(start, count)| {
            let mut out = Vec::new();
            each_line(text, start, count, |line| row(line, &mut out)).then_some(out)
        })
        .collect();
    let mut values = parsed?;
    let mut all = Vec::with_capacity(values.iter().map(Vec::len).sum());
    for v in &mut values {
        all.append(v);
    }
    finish(c, n, end);
    Some(all)
}

/// A line's tokens as the token reader splits them (at ASCII whitespace).
pub struct Tokens<'a> {
    line: &'a [u8],
    pos: usize,
}

impl<'a> Tokens<'a> {
    pub fn new(line: &'a [u8]) -> Self {
        Tokens { line, pos: 0 }
    }

    fn skip_blank(&mut self) {
        while self.pos < self.line.len() && self.line[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// Whether only blanks are left.
    pub fn at_end(&mut self) -> bool {
        self.skip_blank();
        self.pos == self.line.len()
    }

    /// The next whole number ≥ 0 of at most 18 digits, read as it is scanned (the token reader
    /// reads the same value from it; any other token declines). Not the token and then [`int`]:
    /// scanning each row's numbers twice made the 4M-cell Gmsh ASCII load 4 % slower on two
    /// threads (0.821 against 0.791 s, medians of 4 alternating runs).
    pub fn uint(&mut self) -> Option<u64> {
        self.skip_blank();
        let start = self.pos;
        let mut v: u64 = 0;
        while let Some(&b) = self.line.get(self.pos) {
            let d = b.wrapping_sub(b'0');
            if d > 9 {
                if !b.is_ascii_whitespace() {
                    return None;
                }
                break;
            }
            if self.pos - start == 18 {
                // A 19th digit: the token reader decides (and the value cannot overflow here).
                return None;
            }
            v = v * 10 + u64::from(d);
            self.pos += 1;
        }
        (self.pos > start).then_some(v)
    }
}

impl<'a> Iterator for Tokens<'a> {
    type Item = &'a [u8];

    fn next(&mut self) -> Option<&'a [u8]> {
        self.skip_blank();
        let start = self.pos;
        while self.pos < self.line.len() && !self.line[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        (self.pos > start).then(|| &self.line[start..self.pos])
    }
}

/// A line's tokens.
pub fn tokens(line: &[u8]) -> Tokens<'_> {
    Tokens::new(line)
}

/// A whole number of at most 18 digits with an optional sign: on these the token reader's
/// integer parsing agrees (others decline the fast path).
pub use crate::numbers::whole as int;

/// A finite decimal number, as the token reader's float parsing reads it first.
pub fn float(tok: &[u8]) -> Option<f64> {
    crate::numbers::parse_f64(std::str::from_utf8(tok).ok()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::text::parse_int;

    fn ints(line: &[u8], out: &mut [i64]) -> bool {
        let mut t = tokens(line);
        for v in out.iter_mut() {
            match t.next().and_then(int) {
                Some(x) => *v = x,
                None => return false,
            }
        }
        t.at_end()
    }

    /// The fast path leaves the cursor where reading tokens leaves it, or declines and leaves
    /// it alone.
    #[test]
    fn rows_as_tokens_read_them() {
        let many: String = (0..40_000).map(|i| format!("{i} {}\n", 2 * i)).collect();
        for text in [
            format!("3  \n{many}$End\n"),
            format!("3\n{many}"),
            format!("3\n{}", many.trim_end()),
            format!("3\r\n{}\r\n$End", many.trim_end().replace('\n', " \r\n")),
        ] {
            let b = text.as_bytes();
            let mut fast = Cursor::new(b, "t");
            let mut slow = Cursor::new(b, "t");
            fast.token();
            slow.token();
            let got = parse_rows(&mut fast, 40_000, 2, ints).unwrap();
            let mut want = Vec::new();
            for _ in 0..80_000 {
                want.push(slow.int("a number").unwrap());
            }
            assert_eq!(got, want);
            assert_eq!((fast.pos, fast.line), (slow.pos, slow.line));
            assert_eq!(fast.token(), slow.token());
        }
        for bad in [
            "3 4\n1 2\n",
            "3\n1 2\n\n3 4\n",
            "3\n1 2\n3 x4\n",
            "3\n1 2\n",
        ] {
            let mut c = Cursor::new(bad.as_bytes(), "t");
            c.token();
            let at = (c.pos, c.line);
            assert_eq!(parse_rows(&mut c, 2, 2, ints), None, "{bad:?}");
            assert_eq!((c.pos, c.line), at);
        }
        for t in ["0", "-12", "+5", "123456789012345678", "007"] {
            assert_eq!(int(t.as_bytes()), parse_int(t), "{t}");
        }
        for t in ["+-1", "1234567890123456789", "1.0", "", "-", "1e3"] {
            assert_eq!(int(t.as_bytes()), None, "{t}");
        }
        let mut t = tokens(b" 12\t0 007 -1");
        assert_eq!(
            (t.uint(), t.uint(), t.uint(), t.uint()),
            (Some(12), Some(0), Some(7), None)
        );
        assert_eq!(tokens(b"1x").uint(), None);
        assert_eq!(tokens(b"1234567890123456789").uint(), None);
        assert_eq!(
            tokens(b"123456789012345678 ").uint(),
            Some(123_456_789_012_345_678)
        );
        // Long enough to overflow 64 bits (found by fuzzing): declined, not a panic.
        assert_eq!(tokens(b"99999999999999999999999 1").uint(), None);
    }
}
