//! The common case as one merged table: a one-dimensional transfer function.
//!
//! Most scenes map one linearly interpolated scalar field with a SIMPLE_EMITTER (or
//! ABSORPTION_WEIGHTED, or CONSTANT) colormap and a SIMPLE_ABSORBER (or CONSTANT) alphamap,
//! without categories. Then η and χ are piecewise-linear functions of one number `s`, and the
//! two tables can be merged into one over the union of their breakpoints: between two merged
//! knots both are linear, so interpolating the merged rows is the same function. The renderer
//! then needs, per sample, one multiply-add for `s` (barycentric weights times node values) and
//! one table lookup — instead of evaluating every field with its interpolator and both maps
//! through their generic interfaces. [`Mapping::transfer`](super::Mapping::transfer) decides
//! whether a mapping has this form; everything else takes the general path, which gives the
//! same values (up to rounding: the test `transfer_agrees_with_the_general_mapping` checks it).

use super::Table;

/// η as a function of the scalar (before a χ factor).
#[derive(Debug, Clone, Copy)]
pub enum ScalarColor<'a> {
    Table(&'a Table<3>),
    Constant([f64; 3]),
}

/// χ as a function of the scalar.
#[derive(Debug, Clone, Copy)]
pub enum ScalarAlpha<'a> {
    Table(&'a Table<1>),
    Constant(f64),
}

/// One piece of the merged table, as a linear function of `s`.
#[derive(Debug, Clone, Copy)]
struct Piece {
    from: f64,
    base: [f64; 4],
    slope: [f64; 4],
}

/// The merged table and the scalar at every node.
#[derive(Debug, Clone)]
pub struct Transfer1D {
    /// Merged breakpoints, strictly increasing (empty: η and χ are constant).
    knots: Vec<f64>,
    /// Per piece `p ∈ 0..=knots.len()` (see [`Transfer1D::piece`]): `[r, g, b, χ]` at `s` is
    /// `base + (s − from)·slope`, with r, g, b before the χ factor. The pieces outside the
    /// knots are constant (the tables clamp).
    pieces: Vec<Piece>,
    /// η = table · χ (ABSORPTION_WEIGHTED).
    weighted: bool,
    /// χ varies with the scalar (so a weighted η is quadratic along a ray, not linear).
    varying_chi: bool,
    /// The mapped field's value at every node (empty if neither map reads a field).
    pub node_values: Vec<f64>,
}

impl Transfer1D {
    /// Merges the two maps. `node_values` is the field at every node.
    pub fn new(
        color: ScalarColor,
        weighted: bool,
        alpha: ScalarAlpha,
        node_values: Vec<f64>,
    ) -> Transfer1D {
        let mut knots: Vec<f64> = Vec::new();
        if let ScalarColor::Table(t) = color {
            knots.extend_from_slice(t.values());
        }
        if let ScalarAlpha::Table(t) = alpha {
            knots.extend_from_slice(t.values());
        }
        knots.sort_by(f64::total_cmp);
        knots.dedup();
        let row = |s: f64| {
            let rgb = match color {
                ScalarColor::Table(t) => t.eval(s),
                ScalarColor::Constant(c) => c,
            };
            let chi = match alpha {
                ScalarAlpha::Table(t) => t.eval(s)[0],
                ScalarAlpha::Constant(a) => a,
            };
            [rgb[0], rgb[1], rgb[2], chi]
        };
        let rows: Vec<[f64; 4]> = if knots.is_empty() {
            vec![row(0.0)]
        } else {
            knots.iter().map(|&s| row(s)).collect()
        };
        let constant = |r: [f64; 4]| Piece {
            from: 0.0,
            base: r,
            slope: [0.0; 4],
        };
        let mut pieces = vec![constant(rows[0])];
        for p in 1..knots.len() {
            let (a, b) = (rows[p - 1], rows[p]);
            let width = knots[p] - knots[p - 1];
            pieces.push(Piece {
                from: knots[p - 1],
                base: a,
                slope: std::array::from_fn(|k| (b[k] - a[k]) / width),
            });
        }
        if !knots.is_empty() {
            pieces.push(constant(rows[rows.len() - 1]));
        }
        Transfer1D {
            knots,
            pieces,
            weighted,
            varying_chi: matches!(alpha, ScalarAlpha::Table(_)),
            node_values,
        }
    }

    /// The piece of the table holding `s`: 0 below the first knot, `n` from the last knot on,
    /// `i` between knots `i − 1` and `i`.
    #[inline]
    pub fn piece(&self, s: f64) -> usize {
        // Tables are short: counting beats a binary search.
        self.knots.iter().filter(|&&k| k <= s).count()
    }

    /// `(η, χ)` at `s`, evaluated with the formula of `piece` (which must hold `s` up to
    /// rounding: at the ends of a ray segment inside one piece).
    #[inline]
    pub fn eval_in(&self, piece: usize, s: f64) -> ([f64; 3], f64) {
        let p = &self.pieces[piece.min(self.pieces.len() - 1)];
        let d = s - p.from;
        self.finish([
            p.base[0] + d * p.slope[0],
            p.base[1] + d * p.slope[1],
            p.base[2] + d * p.slope[2],
            p.base[3] + d * p.slope[3],
        ])
    }

    /// Piece `piece` as affine functions of `s`: `(from, base, slope)` with
    /// `[η_r, η_g, η_b, χ] = base + (s − from)·slope`, the χ factor of ABSORPTION_WEIGHTED
    /// already applied; `None` where η is quadratic in `s` ([`Transfer1D::quadratic_eta`]).
    pub fn affine_piece(&self, piece: usize) -> Option<(f64, [f64; 4], [f64; 4])> {
        if self.quadratic_eta() {
            return None;
        }
        let p = &self.pieces[piece.min(self.pieces.len() - 1)];
        let (mut base, mut slope) = (p.base, p.slope);
        if self.weighted {
            // χ is constant here (otherwise η would be quadratic).
            for k in 0..3 {
                base[k] *= p.base[3];
                slope[k] *= p.base[3];
            }
        }
        Some((p.from, base, slope))
    }

    /// The range of `s` piece `p` covers: `[lo, hi)`, ±∞ for the outer pieces.
    pub fn piece_range(&self, p: usize) -> (f64, f64) {
        let lo = if p == 0 {
            f64::NEG_INFINITY
        } else {
            self.knots[p - 1]
        };
        let hi = self.knots.get(p).copied().unwrap_or(f64::INFINITY);
        (lo, hi)
    }

    /// η and χ at every one of `nodes` nodes, where that is what the mapping gives at a cell's
    /// node: the field has a value at each node, all finite (a node's barycentric sum
    /// `0·v_0 + … + 1·v_i + …` ([`Transfer1D::scalar`]) is then `v_i` exactly; a non-finite
    /// value at another node of the cell would make it NaN). Methods that map at the nodes
    /// (`interpolateColor`, `interpolateCoeff`) then map once per frame, not once per cell.
    pub fn map_nodes(&self, nodes: usize) -> Option<Vec<([f64; 3], f64)>> {
        use rayon::prelude::*;
        let v = &self.node_values;
        if v.len() != nodes || !v.iter().all(|x| x.is_finite()) {
            return None;
        }
        Some(v.par_iter().map(|&s| self.eval(s)).collect())
    }

    /// `(η, χ)` at `s` (NaN maps like the tables: to their first row).
    #[inline]
    pub fn eval(&self, s: f64) -> ([f64; 3], f64) {
        if s.is_nan() {
            return self.finish(self.pieces[0].base);
        }
        self.eval_in(self.piece(s), s)
    }

    #[inline]
    fn finish(&self, r: [f64; 4]) -> ([f64; 3], f64) {
        let chi = r[3];
        let eta = if self.weighted {
            [r[0] * chi, r[1] * chi, r[2] * chi]
        } else {
            [r[0], r[1], r[2]]
        };
        (eta, chi)
    }

    /// The knots strictly between `a` and `b` (in either order), ascending.
    #[inline]
    pub fn knots_between(&self, a: f64, b: f64) -> &[f64] {
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        let i = self.knots.partition_point(|&k| k <= lo);
        let j = self.knots.partition_point(|&k| k < hi);
        &self.knots[i..j.max(i)]
    }

    /// Whether η varies quadratically along a ray between knots (η = table · χ with both
    /// varying), so that an exact rule needs η in the middle of a piece.
    pub fn quadratic_eta(&self) -> bool {
        self.weighted && self.varying_chi
    }

    /// The table as flat numbers (the GPU's copy): the knots, then per piece `from`, `base`
    /// (r, g, b, χ) and `slope`, r, g, b before the χ factor of [`Transfer1D::weighted`].
    pub fn flat(&self) -> Vec<f64> {
        let mut out = self.knots.clone();
        for p in &self.pieces {
            out.push(p.from);
            out.extend_from_slice(&p.base);
            out.extend_from_slice(&p.slope);
        }
        out
    }

    pub fn knot_count(&self) -> usize {
        self.knots.len()
    }

    /// η = table · χ (ABSORPTION_WEIGHTED).
    pub fn weighted(&self) -> bool {
        self.weighted
    }

    /// The field value at barycentric coordinates `lambda` of a cell with node values `v`.
    #[inline]
    pub fn scalar(v: &[f64; 4], lambda: &[f64; 4]) -> f64 {
        lambda[0] * v[0] + lambda[1] * v[1] + lambda[2] * v[2] + lambda[3] * v[3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::block::Row;

    fn table<const N: usize>(rows: &[&[f64]]) -> Table<N> {
        let rows: Vec<Row> = rows
            .iter()
            .enumerate()
            .map(|(i, n)| Row {
                line: i + 1,
                numbers: n.to_vec(),
            })
            .collect();
        Table::from_rows(&rows, "t").unwrap()
    }

    /// Per node: the same bits as mapping a cell's node through its barycentric sum, and no
    /// per-node table where that sum would differ (a NaN or infinity at a node) or where the
    /// field is not one value per node.
    #[test]
    fn nodes_are_mapped_as_at_a_cells_node() {
        let c = table::<3>(&[&[0.0, 0.0, 1.0, 0.2], &[1.0, 0.5, 0.0, 0.6]]);
        let a = table::<1>(&[&[0.1, 0.4], &[0.9, 0.7]]);
        let values = vec![0.05, 0.3, 0.77, 1.2];
        let t = Transfer1D::new(
            ScalarColor::Table(&c),
            true,
            ScalarAlpha::Table(&a),
            values.clone(),
        );
        let mapped = t.map_nodes(4).unwrap();
        for i in 0..4 {
            let mut lambda = [0.0; 4];
            lambda[i] = 1.0;
            let want = t.eval(Transfer1D::scalar(
                &[values[0], values[1], values[2], values[3]],
                &lambda,
            ));
            assert_eq!(mapped[i], want);
        }
        assert!(t.map_nodes(5).is_none());
        for bad in [f64::NAN, f64::INFINITY] {
            let t = Transfer1D::new(
                ScalarColor::Table(&c),
                false,
                ScalarAlpha::Table(&a),
                vec![0.2, bad, 0.4, 0.5],
            );
            assert!(t.map_nodes(4).is_none());
            // Why: at another node of a cell holding the bad one, the sum is NaN.
            assert!(Transfer1D::scalar(&[0.2, bad, 0.4, 0.5], &[1.0, 0.0, 0.0, 0.0]).is_nan());
        }
    }

    #[test]
    fn the_merged_table_is_both_tables() {
        let c = table::<3>(&[
            &[0.0, 0.0, 1.0, 0.2],
            &[1.0, 0.5, 0.0, 0.6],
            &[1.0, 1.0, 1.0, 0.9],
        ]);
        let a = table::<1>(&[&[0.5, 0.4], &[4.0, 0.7]]);
        for weighted in [false, true] {
            let t = Transfer1D::new(
                ScalarColor::Table(&c),
                weighted,
                ScalarAlpha::Table(&a),
                vec![],
            );
            for k in 0..=120 {
                let s = -0.1 + k as f64 * 0.01;
                let (eta, chi) = t.eval(s);
                let want_chi = a.eval(s)[0];
                let want_eta = c.eval(s).map(|x| if weighted { x * want_chi } else { x });
                assert!((chi - want_chi).abs() < 1e-14, "s = {s}");
                for ch in 0..3 {
                    assert!((eta[ch] - want_eta[ch]).abs() < 1e-14, "s = {s}");
                }
            }
        }
        let t = Transfer1D::new(
            ScalarColor::Table(&c),
            false,
            ScalarAlpha::Table(&a),
            vec![],
        );
        assert_eq!(t.knots_between(0.65, 0.1), &[0.2, 0.4, 0.6]);
        assert_eq!(t.knots_between(0.2, 0.6), &[0.4]);
        assert!(t.knots_between(0.3, 0.3).is_empty());
        let constant = Transfer1D::new(
            ScalarColor::Constant([1.0, 2.0, 3.0]),
            true,
            ScalarAlpha::Constant(0.5),
            vec![],
        );
        assert_eq!(constant.eval(7.0), ([0.5, 1.0, 1.5], 0.5));
        assert!(constant.knots_between(-1.0, 1.0).is_empty());
        assert!(!constant.quadratic_eta());
    }
}
