//! PackBits (Apple Technical Note TN1023; the same code is IFF ILBM's ByteRun1): a header byte
//! `n` in 0…127 is followed by `n + 1` literal bytes, `n` in −127…−1 by one byte repeated
//! `1 − n` times; −128 is skipped. Used by PICT and ILBM, one row (or plane row) at a time.

use super::Bytes;

/// Appends the PackBits code of `row` to `out`. Runs of three or more equal bytes become
/// repeats; everything else is literal (at most 128 bytes per header).
pub fn encode(row: &[u8], out: &mut Vec<u8>) {
    let mut i = 0;
    while i < row.len() {
        let run = row[i..]
            .iter()
            .take(128)
            .take_while(|&&b| b == row[i])
            .count();
        if run >= 3 {
            out.push((1 - run as i32) as i8 as u8);
            out.push(row[i]);
            i += run;
            continue;
        }
        // A literal stretch up to the next run of three (or 128 bytes).
        let start = i;
        while i < row.len() && i - start < 128 {
            if i + 2 < row.len() && row[i] == row[i + 1] && row[i] == row[i + 2] {
                break;
            }
            i += 1;
        }
        out.push((i - start - 1) as u8);
        out.extend_from_slice(&row[start..i]);
    }
}

/// Decodes exactly `out.len()` bytes from `src`; a run that would overflow the row or a code
/// cut short by the end of the data is an error.
pub fn decode(src: &mut Bytes, out: &mut [u8]) -> Result<(), String> {
    let mut n = 0;
    while n < out.len() {
        let at = src.pos();
        let h = src.u8("a PackBits header byte")? as i8;
        let (count, literal) = match h {
            -128 => continue,
            0..=127 => (h as usize + 1, true),
            _ => ((1 - isize::from(h)) as usize, false),
        };
        if n + count > out.len() {
            return Err(super::at(
                at,
                format!(
                    "a PackBits run of {count} bytes overflows the row ({} bytes left)",
                    out.len() - n
                ),
            ));
        }
        if literal {
            out[n..n + count].copy_from_slice(src.take(count, "PackBits literal bytes")?);
        } else {
            let v = src.u8("a PackBits repeated byte")?;
            out[n..n + count].fill(v);
        }
        n += count;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apple_tn1023_example() {
        // The unpacked and packed data of Apple's technical note 1023.
        let unpacked = [
            0xAA, 0xAA, 0xAA, 0x80, 0x00, 0x2A, 0xAA, 0xAA, 0xAA, 0xAA, 0x80, 0x00, 0x2A, 0x22,
            0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA, 0xAA,
        ];
        let packed = [
            0xFE, 0xAA, 0x02, 0x80, 0x00, 0x2A, 0xFD, 0xAA, 0x03, 0x80, 0x00, 0x2A, 0x22, 0xF7,
            0xAA,
        ];
        let mut out = vec![0; unpacked.len()];
        decode(&mut Bytes::new(&packed), &mut out).unwrap();
        assert_eq!(out, unpacked);
        let mut enc = Vec::new();
        encode(&unpacked, &mut enc);
        assert_eq!(enc, packed);
    }

    #[test]
    fn long_rows_and_errors() {
        let row: Vec<u8> = (0..1000)
            .map(|i| if i % 300 < 200 { 7 } else { i as u8 })
            .collect();
        let mut enc = Vec::new();
        encode(&row, &mut enc);
        let mut out = vec![0; row.len()];
        decode(&mut Bytes::new(&enc), &mut out).unwrap();
        assert_eq!(out, row);
        let mut short = vec![0; 3];
        assert!(decode(&mut Bytes::new(&[0xFB, 1]), &mut short).is_err());
        assert!(decode(&mut Bytes::new(&[0x05, 1]), &mut short).is_err());
        assert!(decode(&mut Bytes::new(&[0x01, 1]), &mut short).is_err());
    }
}
