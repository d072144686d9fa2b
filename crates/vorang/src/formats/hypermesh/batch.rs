//! ASCII rows parsed on every core: the complete lines the reader holds are cut into pieces at
//! line ends, each piece is parsed by itself (rows, blank lines, the first marker or bad row), and
//! the pieces are joined in file order.
//!
//! Joining in order is what keeps the result that of a reader going line by line: the block ends
//! at the first marker, the first refused row is the one reported, and a row beyond the block's
//! count is found at the same line. A piece only ever reads its own bytes, straight from the
//! reader's buffer (a copy into a batch cost what the second core saved; docs/performance.md).

use rayon::prelude::*;

use super::row::{AsciiNumber, Line, RowError, RowLines, classify, parse_row};

/// The bytes one piece covers: small enough that every core gets several per batch, large
/// enough that handing one out costs little against parsing it.
const PIECE: usize = 64 << 10;

/// How a piece stopped before its end.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Stop {
    /// An `@marker` line (its text) on the piece's line `line` (0-based).
    Marker { line: usize, text: Vec<u8> },
    /// Row `row` of the piece (0-based, counting good rows before it), on its line `line`, was
    /// refused.
    Row {
        line: usize,
        row: usize,
        error: RowError,
    },
}

/// One piece parsed.
#[derive(Debug)]
pub(super) struct Piece<T> {
    pub values: Vec<T>,
    /// Each row's line, counted from the piece's first line (0).
    pub rows: RowLines,
    pub n_rows: usize,
    /// Lines and bytes the piece used: all of them, or up to and including its stop's line.
    pub lines: usize,
    pub bytes: usize,
    pub stop: Option<Stop>,
}

/// Parses `text` (whole lines, each ending in `\n`) in pieces on rayon's threads; the pieces come
/// back in file order. Pieces after a stop are parsed too (the caller ignores them), which is why
/// the caller keeps a batch near the block's expected size.
pub(super) fn parse_lines<T: AsciiNumber>(text: &[u8], numbers: usize) -> Vec<Piece<T>> {
    let mut ranges = Vec::with_capacity(text.len() / PIECE + 1);
    let mut start = 0;
    while start < text.len() {
        let mut end = (start + PIECE).min(text.len());
        if end < text.len() {
            end += memchr::memchr(b'\n', &text[end..]).map_or(text.len() - end, |i| i + 1);
        }
        ranges.push(start..end);
        start = end;
    }
    ranges
        .into_par_iter()
        .map(|r| parse_piece(&text[r], numbers))
        .collect()
}

/// Parses one piece line by line, up to its first marker or refused row.
pub(super) fn parse_piece<T: AsciiNumber>(text: &[u8], numbers: usize) -> Piece<T> {
    let mut piece = Piece {
        // About what the piece's rows hold: a number with its separator takes a few bytes.
        values: Vec::with_capacity(text.len() / 4),
        rows: RowLines::default(),
        n_rows: 0,
        lines: 0,
        bytes: 0,
        stop: None,
    };
    let mut pos = 0;
    while pos < text.len() {
        let end = memchr::memchr(b'\n', &text[pos..]).map_or(text.len(), |i| pos + i);
        let mut line = &text[pos..end];
        if line.last() == Some(&b'\r') {
            line = &line[..line.len() - 1];
        }
        let here = piece.lines;
        piece.lines += 1;
        pos = (end + 1).min(text.len());
        piece.bytes = pos;
        match classify(line) {
            Line::Blank => {}
            Line::Marker(m) => {
                piece.stop = Some(Stop::Marker {
                    line: here,
                    text: m.to_vec(),
                });
                break;
            }
            Line::Row => match parse_row(line, numbers, &mut piece.values) {
                Ok(()) => {
                    piece.rows.push(piece.n_rows, here);
                    piece.n_rows += 1;
                }
                Err(error) => {
                    piece.stop = Some(Stop::Row {
                        line: here,
                        row: piece.n_rows,
                        error,
                    });
                    break;
                }
            },
        }
    }
    piece
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every way of cutting a text into pieces at line ends gives the rows, lines and stop that
    /// one piece over the whole text gives.
    #[test]
    fn pieces_join_to_the_whole() {
        let text = b"1 2\n\n# c\n3 4\r\n  5 6 # x\n@7\n8 9\n";
        let whole: Piece<i32> = parse_piece(text, 2);
        assert_eq!(whole.values, [1, 2, 3, 4, 5, 6]);
        assert_eq!(whole.n_rows, 3);
        assert_eq!(whole.lines, 6);
        assert_eq!(whole.bytes, text.len() - 4);
        assert_eq!(
            whole.stop,
            Some(Stop::Marker {
                line: 5,
                text: b"@7".to_vec()
            })
        );
        assert_eq!(whole.rows.line_of(2), Some(4));
        let bad: Piece<i32> = parse_piece(b"1 2\n3\n", 2);
        assert_eq!(
            bad.stop,
            Some(Stop::Row {
                line: 1,
                row: 1,
                error: RowError::Count(1)
            })
        );
        let many = "1 2\n".repeat(3 * PIECE / 4);
        let pieces: Vec<Piece<i32>> = parse_lines(many.as_bytes(), 2);
        assert!(pieces.len() >= 3);
        assert_eq!(
            pieces.iter().map(|p| p.n_rows).sum::<usize>(),
            3 * PIECE / 4
        );
        assert_eq!(
            pieces.iter().map(|p| p.bytes).sum::<usize>(),
            many.len(),
            "pieces cover the text exactly"
        );
        assert!(pieces.iter().all(|p| p.stop.is_none()));
    }
}
