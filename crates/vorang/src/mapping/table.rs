//! Lookup tables shared by several methods (thesis: `VRxDataTable`).

use super::block::{BlockError, Row};

/// A piecewise-linear table `value → [f64; N]` with strictly increasing values, linear in
/// between and clamped outside (SIMPLE_EMITTER, ABSORPTION_WEIGHTED, SIMPLE_ABSORBER).
#[derive(Debug, Clone, PartialEq)]
pub struct Table<const N: usize> {
    values: Vec<f64>,
    outputs: Vec<[f64; N]>,
}

impl<const N: usize> Table<N> {
    /// From rows `o1 … oN value`; values must increase strictly (error at the first row that
    /// does not) and outputs must be ≥ 0.
    pub fn from_rows(rows: &[Row], what: &str) -> Result<Self, BlockError> {
        let mut values = Vec::with_capacity(rows.len());
        let mut outputs = Vec::with_capacity(rows.len());
        for (i, r) in rows.iter().enumerate() {
            let v = r.numbers[N];
            if i > 0 && v <= values[i - 1] {
                return Err(BlockError::new(
                    r.line,
                    format!(
                        "table values must increase strictly: {v} follows {} (line {})",
                        values[i - 1],
                        rows[i - 1].line
                    ),
                ));
            }
            let mut o = [0.0; N];
            o.copy_from_slice(&r.numbers[..N]);
            super::block::non_negative(r, &o, what)?;
            values.push(v);
            outputs.push(o);
        }
        Ok(Table { values, outputs })
    }

    /// The table at `v`: linear between rows, the first/last row outside.
    #[inline]
    pub fn eval(&self, v: f64) -> [f64; N] {
        let n = self.values.len();
        if v.is_nan() || v <= self.values[0] {
            return self.outputs[0];
        }
        if v >= self.values[n - 1] {
            return self.outputs[n - 1];
        }
        // First row with value > v; 1 ≤ i ≤ n−1 here.
        let i = self.values.partition_point(|&x| x <= v);
        let (v0, v1) = (self.values[i - 1], self.values[i]);
        let t = (v - v0) / (v1 - v0);
        let (a, b) = (&self.outputs[i - 1], &self.outputs[i]);
        std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
    }

    /// The table values (where the slope may change).
    pub fn values(&self) -> &[f64] {
        &self.values
    }
}

/// A table `byte value → [f64; N]` (CONST_CELL). Values the table does not list map to zero.
#[derive(Debug, Clone, PartialEq)]
pub struct ByteTable<const N: usize> {
    entries: Box<[Option<[f64; N]>; 256]>,
}

impl<const N: usize> ByteTable<N> {
    /// From rows `o1 … oN value`, `value` a whole number 0 … 255, each at most once.
    pub fn from_rows(rows: &[Row], what: &str) -> Result<Self, BlockError> {
        let mut entries = Box::new([None; 256]);
        let mut lines = [0usize; 256];
        for r in rows {
            let v = r.numbers[N];
            if v.fract() != 0.0 || !(0.0..=255.0).contains(&v) {
                return Err(BlockError::new(
                    r.line,
                    format!("expected a byte value 0…255 at the end of the row, found {v}"),
                ));
            }
            let b = v as usize;
            if entries[b].is_some() {
                return Err(BlockError::new(
                    r.line,
                    format!("value {b} is listed twice (also on line {})", lines[b]),
                ));
            }
            let mut o = [0.0; N];
            o.copy_from_slice(&r.numbers[..N]);
            super::block::non_negative(r, &o, what)?;
            entries[b] = Some(o);
            lines[b] = r.line;
        }
        Ok(ByteTable { entries })
    }

    /// The entry for a byte value (zero if the table lacks it).
    #[inline]
    pub fn eval(&self, v: f64) -> [f64; N] {
        if !(0.0..256.0).contains(&v) {
            return [0.0; N];
        }
        self.entries[v as usize].unwrap_or([0.0; N])
    }

    pub fn defined(&self) -> [bool; 256] {
        std::array::from_fn(|i| self.entries[i].is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(data: &[&[f64]]) -> Vec<Row> {
        data.iter()
            .enumerate()
            .map(|(i, n)| Row {
                line: i + 10,
                numbers: n.to_vec(),
            })
            .collect()
    }

    #[test]
    fn tables_interpolate_and_clamp() {
        let t =
            Table::<1>::from_rows(&rows(&[&[0.0, 0.0], &[2.0, 1.0], &[3.0, 3.0]]), "a").unwrap();
        assert_eq!(t.eval(-5.0), [0.0]);
        assert_eq!(t.eval(0.5), [1.0]);
        assert_eq!(t.eval(1.0), [2.0]);
        assert_eq!(t.eval(2.0), [2.5]);
        assert_eq!(t.eval(3.0), [3.0]);
        assert_eq!(t.eval(1e9), [3.0]);
        let single = Table::<3>::from_rows(&rows(&[&[1.0, 2.0, 3.0, 5.0]]), "rgb").unwrap();
        assert_eq!(single.eval(-1.0), [1.0, 2.0, 3.0]);
        assert_eq!(single.eval(9.0), [1.0, 2.0, 3.0]);
    }

    #[test]
    fn non_increasing_values_fail_at_the_first_offending_row() {
        let e = Table::<1>::from_rows(
            &rows(&[&[0.0, 0.0], &[1.0, 1.0], &[2.0, 1.0], &[3.0, 0.5]]),
            "a",
        )
        .unwrap_err();
        assert_eq!(e.line, 12);
        let e = Table::<1>::from_rows(&rows(&[&[-1.0, 0.0]]), "absorption").unwrap_err();
        assert!(e.message.contains("≥ 0"));
    }

    #[test]
    fn byte_tables_look_up_and_default_to_zero() {
        let t = ByteTable::<3>::from_rows(
            &rows(&[&[0.0, 3.0, 1.8, 0.0], &[25.0, 0.0, 0.0, 5.0]]),
            "rgb",
        )
        .unwrap();
        assert_eq!(t.eval(0.0), [0.0, 3.0, 1.8]);
        assert_eq!(t.eval(5.0), [25.0, 0.0, 0.0]);
        assert_eq!(t.eval(4.0), [0.0; 3]);
        assert!(t.defined()[5] && !t.defined()[4]);
        assert!(ByteTable::<1>::from_rows(&rows(&[&[1.0, 2.5]]), "a").is_err());
        assert_eq!(
            ByteTable::<1>::from_rows(&rows(&[&[1.0, 2.0], &[1.0, 2.0]]), "a")
                .unwrap_err()
                .line,
            11
        );
    }
}
