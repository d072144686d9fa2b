//! The time step's label (`label "t = %.3g s"`): a line of text with the shown step's time,
//! drawn into every image and movie frame after the render, as the legend is — white with a
//! black outline in the legend's font ([`super::font`]), in the top left corner (bottom left
//! when the legend's bar runs along the top).
//!
//! The text is a C `printf` format, as Tcl's `format` and Python's `%` read it: `%g`, `%f`,
//! `%e` (and `%G`, `%F`, `%E`) take the step's time, `%d` (`%i`) its number (0-based), `%%` is
//! a percent sign; flags `-+ 0#`, a width and a precision as in C.

use super::font;
use crate::framebuffer::Framebuffer;

/// The label's text for a step: `pattern` with the time and the step number filled in.
pub fn format(pattern: &str, time: f64, index: usize) -> Result<String, String> {
    let mut out = String::new();
    let mut chars = pattern.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let mut spec = Spec::default();
        while let Some(&f) = chars.peek() {
            match f {
                '-' => spec.left = true,
                '+' => spec.plus = true,
                ' ' => spec.space = true,
                '0' => spec.zero = true,
                '#' => spec.alternate = true,
                _ => break,
            }
            chars.next();
        }
        spec.width = number(&mut chars);
        if chars.peek() == Some(&'.') {
            chars.next();
            spec.precision = Some(number(&mut chars));
        }
        let conversion = chars.next().ok_or_else(|| {
            format!("\"{pattern}\" ends inside a conversion: use %g, %f or %e for the time, %d for the step number, %% for a percent sign")
        })?;
        let text = match conversion {
            '%' => "%".to_string(),
            'd' | 'i' => spec.pad(index.to_string(), true),
            'f' | 'F' | 'e' | 'E' | 'g' | 'G' => spec.float(time, conversion),
            other => {
                return Err(format!(
                    "unknown conversion '%{other}' in \"{pattern}\": use %g, %f or %e for the time, %d for the step number, %% for a percent sign"
                ));
            }
        };
        out.push_str(&text);
    }
    Ok(out)
}

/// A whole number at the iterator (0 where there is none); at most 4 digits are read, and
/// widths and precisions above 99 are taken as 99.
fn number(chars: &mut std::iter::Peekable<std::str::Chars>) -> usize {
    let mut n = 0usize;
    while let Some(d) = chars.peek().and_then(|c| c.to_digit(10)) {
        n = (n * 10 + d as usize).min(99);
        chars.next();
    }
    n
}

/// One conversion's flags, width and precision.
#[derive(Debug, Default)]
struct Spec {
    left: bool,
    plus: bool,
    space: bool,
    zero: bool,
    alternate: bool,
    width: usize,
    precision: Option<usize>,
}

impl Spec {
    /// The sign a non-negative number gets.
    fn sign(&self) -> &'static str {
        if self.plus {
            "+"
        } else if self.space {
            " "
        } else {
            ""
        }
    }

    /// `digits` (with its sign, if negative) padded to the width.
    fn pad(&self, digits: String, numeric: bool) -> String {
        let (sign, body) = match digits.strip_prefix('-') {
            Some(rest) => ("-", rest.to_string()),
            None => (self.sign(), digits),
        };
        let len = sign.len() + body.chars().count();
        if len >= self.width {
            return format!("{sign}{body}");
        }
        let fill = self.width - len;
        if self.left {
            format!("{sign}{body}{}", " ".repeat(fill))
        } else if self.zero && numeric {
            format!("{sign}{}{body}", "0".repeat(fill))
        } else {
            format!("{}{sign}{body}", " ".repeat(fill))
        }
    }

    fn float(&self, v: f64, conversion: char) -> String {
        let upper = conversion.is_ascii_uppercase();
        let p = self.precision.unwrap_or(6);
        let text = match conversion.to_ascii_lowercase() {
            'f' => format!("{v:.p$}"),
            'e' => exponential(v, p),
            _ => general(v, p, self.alternate),
        };
        let text = if upper { text.to_uppercase() } else { text };
        self.pad(text, v.is_finite())
    }
}

/// C's `%.pe`: one digit, `p` decimals, an exponent of at least two digits with its sign.
fn exponential(v: f64, p: usize) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let s = format!("{v:.p$e}");
    let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    format!(
        "{mantissa}e{}{:02}",
        if exp < 0 { '-' } else { '+' },
        exp.abs()
    )
}

/// C's `%.pg`: `p` significant digits (1 for 0), fixed notation where the exponent X of the
/// rounded value is −4 ≤ X < p, exponential otherwise; trailing zeros dropped unless
/// `alternate` (`#`).
fn general(v: f64, p: usize, alternate: bool) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let p = p.max(1);
    let rounded = format!("{v:.prec$e}", prec = p - 1);
    let x: i64 = rounded
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    let text = if x >= -4 && x < p as i64 {
        let decimals = (p as i64 - 1 - x).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        exponential(v, p - 1)
    };
    if alternate {
        return text;
    }
    let (mantissa, exp) = match text.find('e') {
        Some(at) => text.split_at(at),
        None => (text.as_str(), ""),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    format!("{mantissa}{exp}")
}

/// Draws `text` into `fb`: in the top left corner, or the bottom left where `bottom` (the
/// legend's bar runs along the top). Font pixels are as large as the legend's.
pub fn draw(fb: &mut Framebuffer, text: &str, bottom: bool) {
    let (w, h) = (fb.width, fb.height);
    let short = w.min(h);
    let s = (short / 256).max(1);
    let margin = (short / 40).max(4);
    let text_h = font::HEIGHT * s;
    let y = if bottom {
        h.saturating_sub(margin + text_h)
    } else {
        margin
    };
    let mut ink = Vec::new();
    font::ink_of(text, margin, y, s, &mut ink);
    super::paint(fb, &ink, |_, _| true);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_as_c_printf_does() {
        let f = |p: &str, t: f64| format(p, t, 7).unwrap();
        assert_eq!(f("t = %.3g s", 0.5), "t = 0.5 s");
        assert_eq!(f("t = %.3g s", 1.25), "t = 1.25 s");
        assert_eq!(f("%.3g", 1234.5), "1.23e+03");
        assert_eq!(f("%.3g", 0.0001234), "0.000123");
        assert_eq!(f("%.3g", 0.00001234), "1.23e-05");
        assert_eq!(f("%g", 0.0), "0");
        assert_eq!(f("%g", 100000.0), "100000");
        assert_eq!(f("%g", 1000000.0), "1e+06");
        assert_eq!(f("%#.3g", 2.0), "2.00");
        assert_eq!(f("%.2f", 2.71834), "2.72");
        assert_eq!(f("%8.2f|", -2.71834), "   -2.72|");
        assert_eq!(f("%-8.2f|", 2.71834), "2.72    |");
        assert_eq!(f("%08.2f", -2.71834), "-0002.72");
        assert_eq!(f("%+.1e", 12345.0), "+1.2e+04");
        assert_eq!(f("%E", 0.5), "5.000000E-01");
        assert_eq!(f("step %d of %03d%%", 0.0), "step 7 of 007%");
        assert_eq!(f("%.0f", 2.5), "2");
    }

    #[test]
    fn bad_formats_say_what_is_allowed() {
        let e = format("t = %s", 0.0, 0).unwrap_err();
        assert!(e.contains("unknown conversion '%s'"), "{e}");
        let e = format("t = %.3", 0.0, 0).unwrap_err();
        assert!(e.contains("ends inside a conversion"), "{e}");
        assert_eq!(format("%99999999999999999999f", 1.0, 0).unwrap().len(), 99);
    }

    #[test]
    fn the_label_is_drawn_top_left_or_bottom_left() {
        let mut fb = Framebuffer::new(64, 64);
        draw(&mut fb, "t = 1", false);
        let white = |fb: &Framebuffer, y0: usize, y1: usize| {
            (y0..y1).any(|y| (0..64).any(|x| fb.pixels[y * 64 + x] == [1.0, 1.0, 1.0, 1.0]))
        };
        assert!(white(&fb, 0, 16) && !white(&fb, 16, 64));
        let mut fb = Framebuffer::new(64, 64);
        draw(&mut fb, "t = 1", true);
        assert!(white(&fb, 48, 64) && !white(&fb, 0, 48));
    }
}
