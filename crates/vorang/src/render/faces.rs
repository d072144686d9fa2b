//! Watertight ray intervals: a cell's per-pixel interval from its faces, one number per face and
//! pixel (`docs/accuracy.md`, "Degenerate views").
//!
//! Each face of a cell projects to a screen triangle. Seen from the viewer the faces are either
//! *entry* faces (the ray enters the cell through them), *exit* faces, or exactly edge-on (zero
//! projected area on the rounded screen positions; they cover nothing). The entry faces tile the
//! cell's footprint, and so do the exit faces — for any four points on screen, whatever rounding
//! did to them. Which face holds a pixel is decided by exact orientation predicates
//! (Shewchuk's `orient2d`) and the top-left rule, which is the same as moving the pixel centre by
//! an infinitesimal `(ε, ε²)`: every pixel centre lies in exactly one entry and one exit face of
//! every cell whose footprint holds it, and a pixel on a face shared by two cells is on that face
//! for both.
//!
//! The depth where a ray crosses a face is computed from the face alone — its nodes in a
//! canonical order (by node number), their screen positions and depths — so both cells of a face
//! get the same number bit for bit: one cell's exit is the next one's entry, and the intervals
//! along a ray telescope. The depth is a convex combination of the face's node depths with the
//! pixel's screen barycentric weights (for perspective, of inverse depths), so it never leaves
//! the face. Faces within rounding of edge-on (a sliver on screen) get their weights in
//! double-double arithmetic, so that even a ray running within 10⁻¹⁶ of a face plane finds a
//! crossing consistent with its neighbours to ~10⁻¹⁶ of the face's depth range.

use crate::mesh::{EDGE_NODES, FACE_NODES};
use crate::predicates::{ROOT_ERROR, boundary};
/// The exact screen predicates live below the faces, the rasteriser and the sort, which all
/// decide by them; re-exported where they were first defined.
pub use crate::predicates::{entry_sign, inside, orient_sign, owns};

/// The cell edge (index into [`EDGE_NODES`]) between local nodes u and v, either way round.
pub const EDGE_OF: [[u8; 4]; 4] = {
    let mut t = [[0u8; 4]; 4];
    let mut e = 0;
    while e < 6 {
        let [i, j] = EDGE_NODES[e];
        t[i][j] = e as u8;
        t[j][i] = e as u8;
        e += 1;
    }
    t
};

/// A face is drawn as a surface (`test`) only if twice its projected area is at least this
/// fraction of its longest edge squared: below, it is seen edge-on up to rounding.
pub const EDGE_ON: f64 = 1e-9;

/// Below this fraction the depth on a face is computed in double-double arithmetic.
const SLIVER: f64 = 1e-3;

/// One face on screen.
#[derive(Debug, Clone, Copy, Default)]
struct Face {
    /// The face's nodes (as local indices 0…3) in positive screen orientation, for the inside
    /// tests.
    pos: [u8; 3],
    /// Screen positions and depth values (orthographic: the depth; perspective: its inverse) of
    /// the face's nodes in canonical order (ascending node number).
    s: [[f64; 2]; 3],
    z: [f64; 3],
    /// Orientation of the canonical triangle (+1/−1), 0 if edge-on.
    orient: i8,
    /// The weights are computed in double-double.
    sliver: bool,
    /// Seen within rounding of edge-on.
    edge_on: bool,
    /// Per edge `pos[k] → pos[k+1]`: shared with another face of the same kind, so it must be
    /// tested (edges on the footprint's outline were decided by its scan conversion).
    inner: [bool; 3],
    /// Not a sliver: the depth value as an affine function of the screen position, from the
    /// canonical first node: `z = plane[0] + plane[1]·(x − s[0].x) + plane[2]·(y − s[0].y)`,
    /// clamped to the face's range `[zmin, zmax]` (evaluated as [`row_part`] `+ plane[1]·x`).
    plane: [f64; 3],
    zmin: f64,
    zmax: f64,
    /// The inner edges as bit masks over the cell edges: the face holds a pixel when the
    /// pixel's side bits ([`Row::sides`]) agree with `want` on `tested`.
    tested: u8,
    want: u8,
}

/// A cell's faces prepared for per-pixel lookups. Valid for footprints that are whole
/// projections (every node in front of the eye).
#[derive(Debug, Clone, Copy)]
pub struct CellFaces {
    faces: [Face; 4],
    screen: [[f64; 2]; 4],
    entry: [u8; 3],
    exit: [u8; 3],
    entries: u8,
    exits: u8,
    perspective: bool,
    /// The cell edges some face must test (bit e for [`EDGE_NODES`]`[e]`).
    needed: u8,
    /// Those edges listed (at most three: the inner edges of two or three faces of one kind
    /// tiling the footprint), and per pattern of a pixel's sides of them (bit j: inside
    /// `inner[j]`) the entry and exit face that hold it ([`CellFaces::faces_in_row`]'s choice,
    /// made once per cell instead of once per run); `NO_PAIR` where a kind has no face.
    inner: [u8; 3],
    inner_count: u8,
    pairs: [[u8; 2]; 8],
}

/// No entry or no exit face ([`CellFaces::spans`] then has no runs).
const NO_PAIR: u8 = u8::MAX;

/// Where a pixel's ray crosses a cell, from its faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceHit {
    pub near: f64,
    pub far: f64,
    pub entry_face: usize,
    pub exit_face: usize,
}

impl CellFaces {
    /// `ids` the cell's node numbers, `screen` their screen positions, `depth` their depths
    /// (> 0 for perspective). `entry_sign` is the frame's constant: a face (in [`FACE_NODES`]
    /// order) is an entry face where `entry_sign · orient2d > 0` (see [`entry_sign`]: the same
    /// convention as the visibility sort's).
    pub fn new(
        ids: [u32; 4],
        screen: &[[f64; 2]; 4],
        depth: &[f64; 4],
        entry_sign: i8,
        perspective: bool,
    ) -> CellFaces {
        let mut faces = [Face::default(); 4];
        let mut kind = [0i8; 4];
        // The depth values once per node, not once per face and node (a division each for a
        // perspective view).
        let z_of = if perspective {
            depth.map(|d| 1.0 / d)
        } else {
            *depth
        };
        for (f, face) in faces.iter_mut().enumerate() {
            let local = FACE_NODES[f];
            let o = orient_sign(screen[local[0]], screen[local[1]], screen[local[2]]);
            kind[f] = o * entry_sign;
            face.pos = if o >= 0 {
                [local[0] as u8, local[1] as u8, local[2] as u8]
            } else {
                [local[0] as u8, local[2] as u8, local[1] as u8]
            };
            // The canonical order (ascending node number), and whether reaching it from
            // `local` takes an odd number of swaps.
            let mut canon = local;
            let mut odd = false;
            for (i, j) in [(0, 1), (1, 2), (0, 1)] {
                if ids[canon[j]] < ids[canon[i]] {
                    canon.swap(i, j);
                    odd = !odd;
                }
            }
            face.s = canon.map(|k| screen[k]);
            face.z = canon.map(|k| z_of[k]);
            let [a, b, c] = face.s;
            // The exact orientation changes sign with every swap of two points.
            face.orient = if odd { -o } else { o };
            // Twice the area against the square of the longest edge: the sine of the face's
            // sharpest angle, roughly — how far from edge-on it is seen.
            let area = ((a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])).abs();
            // Squares as products: `powi` is a library call on the baseline target.
            let len2 = |u: [f64; 2], v: [f64; 2]| {
                let (dx, dy) = (u[0] - v[0], u[1] - v[1]);
                dx * dx + dy * dy
            };
            let longest = len2(a, b).max(len2(b, c)).max(len2(c, a));
            face.sliver = area.is_nan() || area < SLIVER * longest;
            face.edge_on = face.orient == 0 || area.is_nan() || area < EDGE_ON * longest;
            let z = face.z;
            face.zmin = z[0].min(z[1]).min(z[2]);
            face.zmax = z[0].max(z[1]).max(z[2]);
            if !face.sliver {
                // Well away from edge-on: the gradient of z over the screen triangle.
                let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                let (d1, d2) = (z[1] - z[0], z[2] - z[0]);
                let det = e1[0] * e2[1] - e1[1] * e2[0];
                face.plane = [
                    z[0],
                    (d1 * e2[1] - d2 * e1[1]) / det,
                    (d2 * e1[0] - d1 * e2[0]) / det,
                ];
            }
        }
        // An edge of a face is inner if the other face holding it is of the same kind.
        for f in 0..4 {
            for k in 0..3 {
                let (u, v) = (faces[f].pos[k] as usize, faces[f].pos[(k + 1) % 3] as usize);
                // Faces are numbered by their opposite node: the faces holding edge u–v are the
                // ones opposite the two other nodes; `f` is one of them (the nodes sum to 6).
                let other = 6 - f - u - v;
                faces[f].inner[k] = kind[f] != 0 && kind[other] == kind[f];
                if faces[f].inner[k] {
                    // Inside the face means inside u → v: inside the cell edge where u is its
                    // lower node.
                    let bit = 1 << EDGE_OF[u][v];
                    faces[f].tested |= bit;
                    if u < v {
                        faces[f].want |= bit;
                    }
                }
            }
        }
        let mut out = CellFaces {
            faces,
            screen: *screen,
            entry: [0; 3],
            exit: [0; 3],
            entries: 0,
            exits: 0,
            perspective,
            needed: 0,
            inner: [0; 3],
            inner_count: 0,
            pairs: [[NO_PAIR; 2]; 8],
        };
        for face in &faces {
            out.needed |= face.tested;
        }
        for (f, &k) in kind.iter().enumerate() {
            if k > 0 {
                out.entry[out.entries as usize] = f as u8;
                out.entries += 1;
            } else if k < 0 {
                out.exit[out.exits as usize] = f as u8;
                out.exits += 1;
            }
        }
        // At most three inner edges: the faces' projected signed areas (exact `orient2d` of
        // their nodes, outward orientation) sum to zero exactly, so at most three faces are of
        // one kind and then the fourth is of the other — three faces sharing three edges, or
        // two and two sharing one edge each.
        debug_assert!(out.needed.count_ones() <= 3, "{:06b}", out.needed);
        for e in 0..6 {
            if out.needed & (1 << e) != 0 && out.inner_count < 3 {
                out.inner[out.inner_count as usize] = e;
                out.inner_count += 1;
            }
        }
        for pattern in 0..1usize << out.inner_count {
            // The pixel's side bits over all six edges (the others are never tested).
            let mut sides = 0u8;
            for j in 0..out.inner_count as usize {
                if pattern & (1 << j) != 0 {
                    sides |= 1 << out.inner[j];
                }
            }
            if let Some((entry, exit)) = out.faces_for(sides) {
                out.pairs[pattern] = [entry, exit];
            }
        }
        out
    }

    /// Is face `f` (of the kind whose faces tile the footprint) the one holding `p`? Only its
    /// inner edges are tested: `p` is known to be in the footprint.
    #[inline]
    fn holds(&self, f: usize, p: [f64; 2]) -> bool {
        let face = &self.faces[f];
        (0..3).all(|k| {
            !face.inner[k]
                || inside(
                    self.screen[face.pos[k] as usize],
                    self.screen[face.pos[(k + 1) % 3] as usize],
                    p,
                )
        })
    }

    #[inline]
    fn pick(&self, list: &[u8], p: [f64; 2]) -> Option<usize> {
        let (last, rest) = list.split_last()?;
        for &f in rest {
            if self.holds(f as usize, p) {
                return Some(f as usize);
            }
        }
        Some(*last as usize)
    }

    /// The entry and exit face holding pixel centre `(x, y)` of the footprint, and the depths
    /// there (`near ≤ far` up to rounding of ~10⁻¹⁶ relative; the caller decides).
    #[inline]
    pub fn hit(&self, x: f64, y: f64) -> Option<FaceHit> {
        let p = [x, y];
        let entry_face = self.pick(&self.entry[..self.entries as usize], p)?;
        let exit_face = self.pick(&self.exit[..self.exits as usize], p)?;
        Some(FaceHit {
            near: self.depth(entry_face, p),
            far: self.depth(exit_face, p),
            entry_face,
            exit_face,
        })
    }

    /// Whether face `f` is seen edge-on up to rounding (drawn as no surface).
    #[inline]
    pub fn edge_on(&self, f: usize) -> bool {
        self.faces[f].edge_on
    }

    /// The depth where the ray of screen position `p` crosses the plane of face `f`: from the
    /// face's canonical data only, so the same bits for both of its cells.
    #[inline]
    pub fn depth(&self, f: usize, p: [f64; 2]) -> f64 {
        let face = &self.faces[f];
        if face.sliver {
            return sliver_depth(face, p, self.perspective);
        }
        let z = row_part(face, p[1]) + face.plane[1] * p[0];
        let z = clamp(z, face.zmin, face.zmax);
        if self.perspective { 1.0 / z } else { z }
    }

    /// [`CellFaces::depth`] along the row at screen y = `py` for face `f`, as a function of the
    /// pixel centre's x: the same expression, so the same bits, with the row's part computed
    /// once. `None` for a sliver face (use [`CellFaces::depth`]).
    #[inline]
    pub fn depth_row(&self, f: usize, py: f64) -> Option<DepthRow> {
        let face = &self.faces[f];
        if face.sliver {
            return None;
        }
        Some(DepthRow {
            row: row_part(face, py),
            gx: face.plane[1],
            lo: face.zmin,
            hi: face.zmax,
            perspective: self.perspective,
        })
    }

    /// Prepares row `y` of the footprint, pixels `x0..x1`: where each inner edge splits it
    /// (exact predicates, a few tests per edge and row instead of per pixel).
    #[inline]
    pub fn row(&self, y: usize, x0: usize, x1: usize) -> Row {
        let py = y as f64 + 0.5;
        let mut row = Row {
            split: [0; 6],
            rising: [true; 6],
        };
        for e in 0..6 {
            if self.needed & (1 << e) == 0 {
                continue;
            }
            let [i, j] = EDGE_NODES[e];
            let (u, v) = (self.screen[i], self.screen[j]);
            let test = |x: usize| inside(u, v, [x as f64 + 0.5, py]);
            // E(x) = (u.x − x)(v.y − py) − (u.y − py)(v.x − x): slope u.y − v.y.
            let slope = u[1] - v[1];
            let (l, r) = (u[0] * (v[1] - py), (u[1] - py) * v[0]);
            let root = (l - r) / (v[1] - u[1]);
            let margin = ROOT_ERROR * ((l.abs() + r.abs()) / slope.abs() + root.abs());
            row.split[e] = boundary(test, root, margin, slope, x0, x1);
            row.rising[e] = slope >= 0.0;
        }
        row
    }

    /// [`CellFaces::hit`] for pixel x of a prepared row.
    #[inline]
    pub fn hit_in_row(&self, row: &Row, x: usize, y: usize) -> Option<FaceHit> {
        let (entry, exit) = self.faces_in_row(row, x)?;
        let (entry_face, exit_face) = (entry as usize, exit as usize);
        let p = [x as f64 + 0.5, y as f64 + 0.5];
        Some(FaceHit {
            near: self.depth(entry_face, p),
            far: self.depth(exit_face, p),
            entry_face,
            exit_face,
        })
    }
}

impl CellFaces {
    /// The cell edges whose splits [`CellFaces::spans`] reads (bit e for [`EDGE_NODES`]`[e]`).
    pub fn needed(&self) -> u8 {
        self.needed
    }

    /// The entry and exit face holding pixel x of a prepared row (the face choice of
    /// [`CellFaces::hit_in_row`], without the depths).
    #[inline]
    fn faces_in_row(&self, row: &Row, x: usize) -> Option<(u8, u8)> {
        self.faces_for(row.sides(x))
    }

    /// The entry and exit face holding a pixel whose sides of the cell edges are `sides` (bit e
    /// set: inside edge e, from its lower to its higher local node): of each kind, the first
    /// face all of whose inner edges have the pixel on the face's side, else the last.
    #[inline]
    fn faces_for(&self, sides: u8) -> Option<(u8, u8)> {
        let holds = |f: u8| {
            let face = &self.faces[f as usize];
            sides & face.tested == face.want
        };
        let pick = |list: &[u8]| -> Option<u8> {
            let (&last, rest) = list.split_last()?;
            Some(rest.iter().copied().find(|&f| holds(f)).unwrap_or(last))
        };
        let entry = pick(&self.entry[..self.entries as usize])?;
        let exit = pick(&self.exit[..self.exits as usize])?;
        Some((entry, exit))
    }

    /// Row `y`, pixels `from..to`, as runs `x0..x1` with one entry and one exit face each. The
    /// face choice only changes where an inner edge splits the row, so it is settled once per
    /// run (at its first pixel) — the same faces, hence the same depths, as pixel by pixel
    /// ([`CellFaces::hit_in_row`]).
    #[inline]
    pub fn spans(&self, row: &Row, from: usize, to: usize) -> RowRuns {
        let mut out = RowRuns {
            runs: [Run::default(); 4],
            count: 0,
        };
        // The runs end where the (at most three) inner edges split the row: their splits
        // in order, each run's faces looked up by its first pixel's sides.
        let n = self.inner_count as usize;
        let mut at = [to; 3];
        for j in 0..n {
            at[j] = row.split[self.inner[j] as usize].clamp(from, to);
        }
        let sort = |a: &mut [usize; 3], i: usize, j: usize| {
            if a[j] < a[i] {
                a.swap(i, j);
            }
        };
        sort(&mut at, 0, 1);
        sort(&mut at, 1, 2);
        sort(&mut at, 0, 1);
        let mut x = from;
        for next in [at[0], at[1], at[2], to] {
            if next <= x {
                continue;
            }
            let mut pattern = 0;
            for j in 0..n {
                let e = self.inner[j] as usize;
                pattern |= (((x >= row.split[e]) == row.rising[e]) as usize) << j;
            }
            let [entry, exit] = self.pairs[pattern];
            if entry != NO_PAIR {
                out.push(x, next, entry, exit);
            }
            x = next;
        }
        out
    }
}

/// Pixels `x0..x1` of a row with one entry and one exit face.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Run {
    pub x0: usize,
    pub x1: usize,
    pub entry: u8,
    pub exit: u8,
}

/// A row's runs ([`CellFaces::spans`]): at most one more than the three inner edges that split it.
#[derive(Debug, Clone, Copy)]
pub struct RowRuns {
    runs: [Run; 4],
    count: usize,
}

impl RowRuns {
    pub fn runs(&self) -> &[Run] {
        &self.runs[..self.count]
    }

    #[inline(always)]
    fn push(&mut self, x0: usize, x1: usize, entry: u8, exit: u8) {
        self.runs[self.count] = Run {
            x0,
            x1,
            entry,
            exit,
        };
        self.count += 1;
    }
}

/// The part of a face's depth value that is the same along a screen row at `py`:
/// `z0 + gy·(py − a.y) − gx·a.x`, so that the depth value at pixel centre x is one product and
/// one sum, `row_part + gx·x` — the expression [`CellFaces::depth`] and [`DepthRow`] share, so
/// both cells of a face still get the same number. Its rounding is a few ulps of `gx·x` rather
/// than of `gx·(x − a.x)`: for a face one pixel long at x = 4096 (a face that is not a sliver
/// has `|gx|` at most about 10³ times its depth range per pixel) about 10⁻¹⁰ of the face's depth
/// range, where the image keeps 10⁻⁷.
#[inline(always)]
fn row_part(face: &Face, py: f64) -> f64 {
    let [z0, gx, gy] = face.plane;
    let a = face.s[0];
    (z0 + gy * (py - a[1])) - gx * a[0]
}

/// The larger of `a` and `b` by a comparison and a select: one instruction in lanes, where
/// `f64::max`'s NaN rule costs three. A NaN `a` gives `b`, as `f64::max` would; callers keep
/// NaN out of `b`.
#[inline(always)]
pub fn max_select(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// The smaller of `a` and `b`, as [`max_select`]: a NaN `a` gives `b`.
#[inline(always)]
pub fn min_select(a: f64, b: f64) -> f64 {
    if a < b { a } else { b }
}

/// `z` clamped to `[lo, hi]`; a NaN `z` becomes `lo`, as `z.max(lo).min(hi)` would give.
#[inline(always)]
fn clamp(z: f64, lo: f64, hi: f64) -> f64 {
    min_select(max_select(z, lo), hi)
}

/// A face's depth along one screen row ([`CellFaces::depth_row`]).
#[derive(Debug, Clone, Copy)]
pub struct DepthRow {
    row: f64,
    gx: f64,
    lo: f64,
    hi: f64,
    perspective: bool,
}

impl DepthRow {
    /// The depth at pixel centre `px`, [`CellFaces::depth`]'s expression term by term, for a
    /// row known to be perspective (`PERSP`) or not, so that a loop over pixels has no branch
    /// (or masked division) in it.
    #[inline(always)]
    pub fn at_view<const PERSP: bool>(&self, px: f64) -> f64 {
        debug_assert_eq!(PERSP, self.perspective);
        let z = clamp(self.row + self.gx * px, self.lo, self.hi);
        if PERSP { 1.0 / z } else { z }
    }

    pub fn perspective(&self) -> bool {
        self.perspective
    }
}

/// One row of a footprint prepared by [`CellFaces::row`]: per cell edge (in [`EDGE_NODES`]
/// order, from its lower to its higher local node), the pixel where the row crosses it — inside
/// the edge from there on (`rising`) or before it.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    split: [usize; 6],
    rising: [bool; 6],
}

impl Row {
    /// A row whose splits were computed elsewhere ([`super::rows`]), with the same meaning.
    pub fn new(split: [usize; 6], rising: [bool; 6]) -> Row {
        Row { split, rising }
    }

    /// Bit e set where pixel `x` of the row is inside cell edge e (from its lower to its
    /// higher local node): from the split on for a rising edge, before it otherwise.
    #[inline]
    fn sides(&self, x: usize) -> u8 {
        let mut bits = 0;
        for e in 0..6 {
            bits |= (((x >= self.split[e]) == self.rising[e]) as u8) << e;
        }
        bits
    }
}

/// A double-double number `hi + lo`.
#[derive(Debug, Clone, Copy)]
struct Dd(f64, f64);

#[inline]
fn two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    let bb = s - a;
    Dd(s, (a - (s - bb)) + (b - bb))
}

#[inline]
fn quick(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd(s, b - (s - a))
}

impl Dd {
    fn add(self, o: Dd) -> Dd {
        let s = two_sum(self.0, o.0);
        quick(s.0, s.1 + self.1 + o.1)
    }
    fn neg(self) -> Dd {
        Dd(-self.0, -self.1)
    }
    fn mul(self, o: Dd) -> Dd {
        let p = self.0 * o.0;
        let e = self.0.mul_add(o.0, -p) + (self.0 * o.1 + self.1 * o.0);
        quick(p, e)
    }
    fn diff(a: f64, b: f64) -> Dd {
        two_sum(a, -b)
    }
    fn value(self) -> f64 {
        self.0 + self.1
    }
}

/// [`CellFaces::depth`] for a face within rounding of edge-on: the screen barycentric weights in
/// double-double.
#[cold]
fn sliver_depth(face: &Face, p: [f64; 2], perspective: bool) -> f64 {
    let [a, b, c] = face.s;
    let cross = |u: [f64; 2], v: [f64; 2]| {
        Dd::diff(u[0], p[0])
            .mul(Dd::diff(v[1], p[1]))
            .add(Dd::diff(u[1], p[1]).mul(Dd::diff(v[0], p[0])).neg())
    };
    let sign = f64::from(face.orient);
    let clamp = |d: Dd| {
        let d = Dd(sign * d.0, sign * d.1);
        if d.value() > 0.0 { d } else { Dd(0.0, 0.0) }
    };
    let w = [clamp(cross(b, c)), clamp(cross(c, a)), clamp(cross(a, b))];
    let sum = w[0].add(w[1]).add(w[2]);
    let z = face.z;
    let num = w[0]
        .mul(Dd(z[0], 0.0))
        .add(w[1].mul(Dd(z[1], 0.0)))
        .add(w[2].mul(Dd(z[2], 0.0)));
    let (n, d) = if perspective { (sum, num) } else { (num, sum) };
    if d.value() == 0.0 {
        let mean = (z[0] + z[1] + z[2]) / 3.0;
        return if perspective { 1.0 / mean } else { mean };
    }
    // n / d with one correction step.
    let q = n.0 / d.0;
    let r = n.add(Dd(q, 0.0).mul(d).neg());
    q + r.value() / d.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run's depths ([`CellFaces::depth_row`], [`DepthRow::at_view`]) are [`CellFaces::depth`]'s
    /// bits for every face that is not a sliver, orthographic and perspective: the span kernel's
    /// pixels and the per-pixel path's (slivers, clipped cells) meet at shared faces with the
    /// same number.
    #[test]
    fn a_rows_depths_are_the_depths_bit_for_bit() {
        let mut rng = crate::mesh::generate::SplitMix64(29);
        let mut checked = 0;
        for _ in 0..300 {
            let screen: [[f64; 2]; 4] =
                std::array::from_fn(|_| [600.0 * rng.next_f64(), 600.0 * rng.next_f64()]);
            let depth: [f64; 4] = std::array::from_fn(|_| 0.5 + 5.0 * rng.next_f64());
            for perspective in [false, true] {
                let faces = CellFaces::new([5, 1, 8, 3], &screen, &depth, -1, perspective);
                for f in 0..4 {
                    for _ in 0..8 {
                        let py = (600.0 * rng.next_f64()).floor() + 0.5;
                        let Some(row) = faces.depth_row(f, py) else {
                            continue;
                        };
                        for _ in 0..8 {
                            let px = (600.0 * rng.next_f64()).floor() + 0.5;
                            let want = faces.depth(f, [px, py]).to_bits();
                            let got = if perspective {
                                row.at_view::<true>(px)
                            } else {
                                row.at_view::<false>(px)
                            };
                            assert_eq!(got.to_bits(), want, "face {f} at ({px}, {py})");
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked > 50_000, "{checked}");
    }

    /// Projected orthographically (screen = (x, −y)), every pixel centre of a unit-ish cell lies
    /// in exactly one entry and one exit face, and the depths there are the exact ray–plane
    /// crossings.
    #[test]
    fn entry_and_exit_faces_tile_the_footprint_and_give_the_plane_depths() {
        let mut rng = crate::mesh::generate::SplitMix64(3);
        let mut checked = 0;
        for _ in 0..200 {
            let mut p = [[0.0; 3]; 4];
            for q in &mut p {
                *q = [
                    8.0 * rng.next_f64(),
                    8.0 * rng.next_f64(),
                    -1.0 - 8.0 * rng.next_f64(),
                ];
            }
            if crate::mesh::orientation(p[0], p[1], p[2], p[3]) < 0.0 {
                p.swap(0, 1);
            }
            let Some(cell) = crate::render::cell::EyeCell::new(&p) else {
                continue;
            };
            let screen = p.map(|q| [q[0], -q[1]]);
            let depth = p.map(|q| -q[2]);
            let faces = CellFaces::new([4, 9, 2, 7], &screen, &depth, entry_sign(false), false);
            for j in -9..1 {
                for i in 0..9 {
                    let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                    let ray = crate::scene::Ray {
                        origin: [x, -y, 0.0],
                        dir: [0.0, 0.0, -1.0],
                    };
                    let Some(iv) = cell.interval(&ray) else {
                        continue;
                    };
                    if iv.far - iv.near < 1e-6 {
                        continue;
                    }
                    let hit = faces.hit(x, y).expect("a pixel of the footprint");
                    assert_eq!(
                        (hit.entry_face, hit.exit_face),
                        (iv.entry_face, iv.exit_face)
                    );
                    assert!((hit.near - iv.near).abs() < 1e-9, "{hit:?} {iv:?}");
                    assert!((hit.far - iv.far).abs() < 1e-9, "{hit:?} {iv:?}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 500, "{checked}");
    }

    /// The row-prepared lookup equals the per-pixel one everywhere, also for nodes on pixel
    /// centres and edges through them (coordinates on a half-pixel grid).
    #[test]
    fn rows_and_pixels_pick_the_same_faces() {
        let mut rng = crate::mesh::generate::SplitMix64(8);
        let mut compared = 0;
        for trial in 0..300 {
            let grid = trial % 2 == 0;
            let mut p = [[0.0; 3]; 4];
            for q in &mut p {
                let mut c = || {
                    let v = 12.0 * rng.next_f64();
                    if grid { (2.0 * v).round() / 2.0 } else { v }
                };
                *q = [c(), c(), -1.0 - c()];
            }
            let o = crate::mesh::orientation(p[0], p[1], p[2], p[3]);
            if o == 0.0 {
                continue;
            }
            if o < 0.0 {
                p.swap(0, 1);
            }
            let screen = p.map(|q| [q[0], -q[1] + 12.0]);
            let depth = p.map(|q| -q[2]);
            let faces = CellFaces::new([3, 1, 4, 0], &screen, &depth, entry_sign(false), false);
            for y in 0..12 {
                let row = faces.row(y, 0, 12);
                // The runs: consecutive, and each pixel in the one whose faces it has.
                let (from, to) = (3 * (trial % 3), 12 - 2 * (trial % 4));
                let mut runs = faces.spans(&row, from, to).runs().to_vec();
                for x in 0..12 {
                    let a = faces.hit(x as f64 + 0.5, y as f64 + 0.5);
                    let b = faces.hit_in_row(&row, x, y);
                    assert_eq!(a, b, "trial {trial}, pixel ({x}, {y})");
                    if (from..to).contains(&x) {
                        let run = runs.iter().find(|r| (r.x0..r.x1).contains(&x));
                        let faces_of =
                            |h: Option<FaceHit>| h.map(|h| (h.entry_face as u8, h.exit_face as u8));
                        assert_eq!(
                            run.map(|r| (r.entry, r.exit)),
                            faces_of(b),
                            "trial {trial}, pixel ({x}, {y})"
                        );
                    }
                    compared += 1;
                }
                runs.retain(|r| r.x0 < r.x1);
                assert!(runs.windows(2).all(|w| w[0].x1 == w[1].x0), "{runs:?}");
                if let (Some(a), Some(b)) = (runs.first(), runs.last()) {
                    assert!(a.x0 >= from && b.x1 <= to);
                }
            }
        }
        assert!(compared > 10_000);
    }

    /// The footprint's outline covers exactly the pixels its entry faces cover, and exactly those
    /// its exit faces cover, each once (full three-edge tests), with nodes and edges on centres.
    #[test]
    fn entry_faces_and_exit_faces_each_tile_the_outline() {
        use crate::render::raster::{Rect, rasterize_convex};
        let mut rng = crate::mesh::generate::SplitMix64(21);
        let rect = Rect {
            x0: 0,
            y0: 0,
            x1: 10,
            y1: 10,
        };
        let mut covered = 0;
        for _ in 0..400 {
            let mut p = [[0.0; 3]; 4];
            for q in &mut p {
                let mut c = || (20.0 * rng.next_f64()).round() / 2.0;
                *q = [c(), c(), -1.0 - c()];
            }
            let o = crate::mesh::orientation(p[0], p[1], p[2], p[3]);
            if o == 0.0 {
                continue;
            }
            if o < 0.0 {
                p.swap(0, 1);
            }
            let screen = p.map(|q| [q[0], 10.0 - q[1]]);
            let depth = p.map(|q| -q[2]);
            let faces = CellFaces::new([0, 1, 2, 3], &screen, &depth, entry_sign(false), false);
            let mut outline = vec![0u8; 100];
            // The outline: the hull of the four screen points, as the footprint gives it.
            let fpr = crate::render::footprint::footprint(
                [0, 1, 2, 3],
                &p,
                &screen,
                &crate::scene::Projector::new(None, [10.0, 10.0, 1.0], 10, 10).unwrap(),
            )
            .unwrap();
            if let Some((v, n)) = fpr.hull() {
                rasterize_convex(&v[..n], rect, |x, y| outline[y * 10 + x] += 1);
            }
            for kind in [
                &faces.entry[..faces.entries as usize],
                &faces.exit[..faces.exits as usize],
            ] {
                let mut count = vec![0u8; 100];
                for &f in kind {
                    let pos = faces.faces[f as usize].pos.map(|k| screen[k as usize]);
                    for y in 0..10 {
                        for x in 0..10 {
                            let q = [x as f64 + 0.5, y as f64 + 0.5];
                            if (0..3).all(|k| inside(pos[k], pos[(k + 1) % 3], q)) {
                                count[y * 10 + x] += 1;
                            }
                        }
                    }
                }
                assert_eq!(count, outline, "{p:?}");
            }
            covered += outline.iter().filter(|&&c| c > 0).count();
        }
        assert!(covered > 1000, "{covered}");
    }

    /// Two cells sharing a face (nodes 10, 20, 30), listed in different orders with different
    /// fourth nodes, compute the same depth on it bit for bit — for a face within rounding of
    /// edge-on (double-double path) and for an ordinary one (plane path) — and the depth stays in
    /// the face's depth range.
    #[test]
    fn both_cells_of_a_face_get_the_same_depth_bits() {
        let (a, b) = ([0.5, 0.5 - 1e-14], [8.5, 0.5 + 1e-14]);
        for (c, sliver) in [([4.5, 0.5 - 3e-14], true), ([4.5, 6.0], false)] {
            let z = [2.0, 7.0, 4.0];
            let cell1 = CellFaces::new(
                [10, 20, 30, 40],
                &[a, b, c, [3.0, 9.0]],
                &[z[0], z[1], z[2], 1.0],
                entry_sign(false),
                false,
            );
            let cell2 = CellFaces::new(
                [30, 50, 10, 20],
                &[c, [6.0, -7.0], a, b],
                &[z[2], 9.0, z[0], z[1]],
                entry_sign(false),
                false,
            );
            // The shared face is opposite node 40 (local 3) in the first cell and node 50
            // (local 1) in the second.
            assert_eq!(cell1.faces[3].sliver, sliver);
            assert_eq!(cell2.faces[1].sliver, sliver);
            for x in 0..9 {
                for dy in [-2e-14, 0.0, 1e-14, 0.25] {
                    let p = [x as f64 + 0.5, 0.5 + dy];
                    let (d1, d2) = (cell1.depth(3, p), cell2.depth(1, p));
                    assert_eq!(d1.to_bits(), d2.to_bits(), "{p:?}: {d1} vs {d2}");
                    assert!((2.0..=7.0).contains(&d1), "{p:?}: {d1}");
                }
            }
        }
    }
}
