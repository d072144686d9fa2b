//! A 5 × 7 bitmap font for the legend's numbers: digits, `.`, `-`, `+`, `e` and a space. Small
//! on purpose — the labels are numbers, and a font dependency would outweigh the renderer's
//! other image code.

/// Glyph width and height in font pixels; characters advance by `ADVANCE`.
pub const WIDTH: usize = 5;
pub const HEIGHT: usize = 7;
pub const ADVANCE: usize = 6;

/// The rows of a glyph, top first; bit 4 is the leftmost pixel. Unknown characters are blank.
fn glyph(c: char) -> [u8; HEIGHT] {
    match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        '-' => [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        'e' => [0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E],
        _ => [0; HEIGHT],
    }
}

/// Whether font pixel `(x, y)` of `c` is set.
pub fn ink(c: char, x: usize, y: usize) -> bool {
    x < WIDTH && y < HEIGHT && glyph(c)[y] & (0x10 >> x) != 0
}

/// The width of `text` in font pixels (no trailing gap).
pub fn text_width(text: &str) -> usize {
    (text.chars().count() * ADVANCE).saturating_sub(ADVANCE - WIDTH)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyphs_fit_their_box_and_digits_differ() {
        for c in "0123456789.-+e".chars() {
            assert!(glyph(c).iter().all(|r| r & !0x1F == 0), "{c}");
            assert!(glyph(c).iter().any(|&r| r != 0), "{c}");
        }
        let digits: Vec<_> = "0123456789".chars().map(glyph).collect();
        for (i, a) in digits.iter().enumerate() {
            assert!(digits[i + 1..].iter().all(|b| a != b));
        }
        assert!(ink('1', 2, 0) && !ink('1', 0, 0));
        assert_eq!(text_width("0.5"), 17);
    }
}
