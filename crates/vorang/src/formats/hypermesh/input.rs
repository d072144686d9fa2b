//! A streaming reader that hands out lines (for the header and ASCII blocks) and raw bytes (for
//! BINARY blocks) while counting lines and the bytes still to come.
//!
//! Streaming rather than reading the whole file keeps peak memory near the size of the final mesh;
//! knowing how many bytes remain lets block readers refuse absurd counts before allocating.

use std::io::{self, BufRead, Read};

/// The longest line a HyperMesh file may have (16 MiB: far beyond any header or data row).
pub const MAX_LINE: usize = 16 << 20;

pub struct Input<R> {
    reader: R,
    /// Line number of the line most recently returned by [`Input::next_line`] (1-based).
    pub line: usize,
    buf: Vec<u8>,
    remaining: Option<u64>,
}

impl<R: BufRead> Input<R> {
    /// `size` is the total number of bytes the source holds, if known.
    pub fn new(reader: R, size: Option<u64>) -> Self {
        Input {
            reader,
            line: 0,
            buf: Vec::with_capacity(256),
            remaining: size,
        }
    }

    /// Bytes not yet consumed, if the source size is known.
    pub fn remaining(&self) -> Option<u64> {
        self.remaining
    }

    fn consumed(&mut self, n: usize) {
        if let Some(r) = &mut self.remaining {
            *r = r.saturating_sub(n as u64);
        }
    }

    /// The next line without its `\n` (and a trailing `\r`) with its line number, or `None` at
    /// end of input. A line longer than [`MAX_LINE`] is an error (`/dev/zero` is not a header).
    /// A UTF-8 byte-order mark at the start of the file is skipped.
    pub fn next_line(&mut self) -> io::Result<Option<(usize, &[u8])>> {
        self.buf.clear();
        let n = (&mut self.reader)
            .take(MAX_LINE as u64 + 1)
            .read_until(b'\n', &mut self.buf)?;
        if n == 0 {
            return Ok(None);
        }
        self.consumed(n);
        self.line += 1;
        if n > MAX_LINE && self.buf.last() != Some(&b'\n') {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "line {} is longer than {} MiB: not a HyperMesh file",
                    self.line,
                    MAX_LINE >> 20
                ),
            ));
        }
        if self.line == 1 && self.buf.starts_with(b"\xEF\xBB\xBF") {
            self.buf.drain(..3);
        }
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
        }
        if self.buf.last() == Some(&b'\r') {
            self.buf.pop();
        }
        Ok(Some((self.line, &self.buf)))
    }

    /// Hands `f` the complete lines at the front of the reader's buffer, about `cap` bytes of
    /// them (at least one line), with the number of the first; `f` returns what it made and the
    /// bytes and lines it used, which are then consumed; returns what `f` made and those bytes.
    /// `None` when the buffer holds no whole
    /// line (a line longer than the buffer, or the file's last line without `\n`): read that one
    /// with [`Input::next_line`].
    ///
    /// Parsing straight from the buffer is what lets the rows of a batch be parsed in parallel
    /// without copying them first.
    pub fn with_lines<T>(
        &mut self,
        cap: usize,
        f: impl FnOnce(&[u8], usize) -> (T, usize, usize),
    ) -> io::Result<Option<(T, usize)>> {
        if self.line == 0 {
            // The first line may carry a byte-order mark: next_line strips it.
            return Ok(None);
        }
        let avail = self.reader.fill_buf()?;
        let head = &avail[..cap.min(avail.len())];
        let end = match memchr::memrchr(b'\n', head) {
            Some(i) => i + 1,
            None => match memchr::memchr(b'\n', &avail[head.len()..]) {
                Some(i) => head.len() + i + 1,
                None => return Ok(None),
            },
        };
        let (made, bytes, lines) = f(&avail[..end], self.line + 1);
        debug_assert!(bytes <= end);
        self.reader.consume(bytes);
        self.consumed(bytes);
        self.line += lines;
        Ok(Some((made, bytes)))
    }

    /// Reads up to `n` bytes, appending them to `out`; returns how many were read (fewer only at
    /// end of input). Once the buffer is drained, large reads go from the file straight into
    /// `out` (the reader's buffer is sized for ASCII batches; copying BINARY blocks through it
    /// cost about 5 % of a load).
    pub fn read_bytes(&mut self, n: usize, out: &mut Vec<u8>) -> io::Result<usize> {
        let before = out.len();
        (&mut self.reader).take(n as u64).read_to_end(out)?;
        let done = out.len() - before;
        self.consumed(done);
        Ok(done)
    }

    /// Consumes one `\n` if it is the next byte (the optional newline after a BINARY block).
    /// It ends the line the binary data sat on, so the line count advances.
    pub fn skip_newline(&mut self) -> io::Result<()> {
        let avail = self.reader.fill_buf()?;
        if avail.first() == Some(&b'\n') {
            self.reader.consume(1);
            self.consumed(1);
            self.line += 1;
        }
        Ok(())
    }

    /// Advances the line counter by the newlines inside binary data, so that line numbers after
    /// a BINARY block still match what an editor shows.
    pub fn count_lines_in(&mut self, bytes: &[u8]) {
        self.line += crate::formats::text::count_lines(bytes);
    }
}
