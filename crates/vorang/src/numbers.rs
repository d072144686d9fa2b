//! The number grammar shared by all our text formats (HyperMesh ASCII blocks, map files):
//! decimal numbers with optional sign, fraction and exponent — no `inf`, `nan` or hex, so that
//! a typo never becomes a silent infinity.

/// `[+-]? (digits [. digits*] | . digits) ([eE] [+-]? digits)?` — no `inf`, `nan` or hex.
pub fn is_decimal(tok: &[u8]) -> bool {
    let mut i = 0;
    if matches!(tok.first(), Some(b'+' | b'-')) {
        i = 1;
    }
    let int_digits = tok[i..].iter().take_while(|b| b.is_ascii_digit()).count();
    i += int_digits;
    let mut frac_digits = 0;
    if tok.get(i) == Some(&b'.') {
        i += 1;
        frac_digits = tok[i..].iter().take_while(|b| b.is_ascii_digit()).count();
        i += frac_digits;
    }
    if int_digits + frac_digits == 0 {
        return false;
    }
    if matches!(tok.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(tok.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        let exp_digits = tok[i..].iter().take_while(|b| b.is_ascii_digit()).count();
        if exp_digits == 0 {
            return false;
        }
        i += exp_digits;
    }
    i == tok.len()
}

/// A whole number `[+-]? digits` of at most 18 digits (so it cannot overflow an `i64`).
pub fn whole(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok.first() {
        Some(b'-') => (true, &tok[1..]),
        Some(b'+') => (false, &tok[1..]),
        _ => (false, tok),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v * 10 + i64::from(d - b'0');
    }
    Some(if neg { -v } else { v })
}

/// A finite f64 written in the decimal grammar.
pub fn parse_f64(tok: &str) -> Option<f64> {
    if !is_decimal(tok.as_bytes()) {
        return None;
    }
    tok.parse::<f64>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimal_grammar() {
        for ok in ["0", "-1", "+2.5", ".5", "5.", "1e5", "1.5E-7", "-0.0"] {
            assert!(is_decimal(ok.as_bytes()), "{ok}");
        }
        for bad in [
            "", "-", ".", "e5", "1e", "inf", "nan", "NaN", "0x10", "1,5", "1e+", "--1",
        ] {
            assert!(!is_decimal(bad.as_bytes()), "{bad}");
        }
    }

    #[test]
    fn parse_rejects_overflow() {
        assert_eq!(parse_f64("1.5e3"), Some(1500.0));
        assert_eq!(parse_f64("1e999"), None);
        assert_eq!(parse_f64("inf"), None);
    }
}
