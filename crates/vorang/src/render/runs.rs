//! Visibility exact per pixel for any mesh: per-pixel *runs* of cells chained through their
//! shared faces (thesis 2.2.2.2; docs/architecture.md "order exact per pixel").
//!
//! Along one ray, the cells it passes form stretches of face-adjacent cells: a stretch starts
//! where the ray enters the mesh (a boundary face, the near plane) and ends where it leaves.
//! Every fragment (one cell at one pixel) knows the faces its ray enters and leaves through
//! ([`super::faces`]), so it knows its neighbours along the ray *exactly*: the cell across its
//! exit face is the next one behind it, the cell across its entry face the next one in front.
//! A run is a chain of such fragments with their contributions composed into one map
//! `I ↦ I·θ + b`; a fragment joins the run whose front cell is its exit neighbour (in front of
//! it), the run whose back cell is its entry neighbour (behind it), or both (merging them), or
//! starts a run. That is right whatever order the fragments arrive in — visibility cycles and
//! all. Runs are disjoint stretches of the ray, so at the end they are sorted by depth and
//! composited.
//!
//! The sort still matters for speed and memory: in MPVO(NC) order almost every fragment extends
//! the run it connects to, so a pixel holds one run per stretch of mesh its ray crosses. Used only
//! where the sort is not known to be exact (non-convex meshes, broken cycles); convex meshes
//! composite straight into the pixel.

/// Where a fragment lies along its ray: its cell, the cells across its entry and exit faces
/// ([`crate::mesh::NO_NEIGHBOR`] at the mesh boundary or where it is clipped), and its depth interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    pub cell: u32,
    pub entry_neighbor: u32,
    pub exit_neighbor: u32,
    /// Whether the neighbour across the entry (exit) face came earlier in the compositing
    /// order — only then can a run end at it; otherwise its list is not searched.
    pub entry_earlier: bool,
    pub exit_earlier: bool,
    pub near: f64,
    pub far: f64,
}

/// A chain of fragments: front and back cell and depth, and the composed map.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Run {
    b: [f64; 3],
    theta: f64,
    front: u32,
    back: u32,
    near: f64,
    far: f64,
}

impl Run {
    /// Whether the run changes no light (`b = 0`, `θ = 1`): cells clipped away or only grazed.
    #[inline]
    fn is_identity(&self) -> bool {
        self.theta == 1.0 && self.b.iter().all(|v| v.to_bits() == 0)
    }
}

/// `outer ∘ inner`: light passes `inner` first.
#[inline]
fn compose(outer: ([f64; 3], f64), inner: ([f64; 3], f64)) -> ([f64; 3], f64) {
    let (bo, to) = outer;
    let (bi, ti) = inner;
    (
        [bi[0] * to + bo[0], bi[1] * to + bo[1], bi[2] * to + bo[2]],
        ti * to,
    )
}

const NONE: u32 = u32::MAX;

/// The runs of every pixel of a tile: one arena, a list per pixel (no allocation per pixel).
#[derive(Debug, Default)]
pub struct Runs {
    /// Per pixel: its first run in `arena`, or `NONE`.
    heads: Vec<u32>,
    /// Per pixel: how many runs it holds.
    counts: Vec<u16>,
    arena: Vec<(Run, u32)>,
    /// Scratch for sorting a pixel's runs.
    sorted: Vec<Run>,
    /// The most runs any pixel held (memory report).
    pub most: usize,
    /// Pixels whose ray passes two runs that overlap in depth (interpenetrating cells), and a
    /// few such pairs of cells (the runs' cells at the overlapping ends).
    pub overlaps: usize,
    pub overlap_cells: Vec<(u32, u32)>,
}

/// Runs overlapping by more than this fraction of their lengths interpenetrate (less is
/// rounding, as where two bodies touch).
const OVERLAP: f64 = 1e-9;

/// At most this many example pairs are kept per tile.
const EXAMPLES: usize = 64;

impl Runs {
    pub fn new(pixels: usize) -> Runs {
        Runs {
            heads: vec![NONE; pixels],
            counts: vec![0; pixels],
            arena: Vec::with_capacity(pixels + pixels / 4),
            sorted: Vec::new(),
            most: 0,
            overlaps: 0,
            overlap_cells: Vec::new(),
        }
    }

    /// Adds fragment `link` with contribution `piece` (`I ↦ I·θ + b`) to pixel `slot`.
    #[inline]
    pub fn add(&mut self, slot: usize, link: Link, piece: ([f64; 3], f64)) {
        // The run the fragment lies in front of (its front cell is across our exit face) and the
        // one it lies behind (its back cell is across our entry face). In a good order only one
        // neighbour came earlier, and the run it ends is first in the list (move to front).
        let behind = if link.exit_earlier {
            self.find(slot, |r| r.front == link.exit_neighbor)
        } else {
            None
        };
        let before = if link.entry_earlier {
            self.find(slot, |r| r.back == link.entry_neighbor)
        } else {
            None
        };
        match (before, behind) {
            (None, None) => {
                let run = Run {
                    b: piece.0,
                    theta: piece.1,
                    front: link.cell,
                    back: link.cell,
                    near: link.near,
                    far: link.far,
                };
                self.arena.push((run, self.heads[slot]));
                self.heads[slot] = (self.arena.len() - 1) as u32;
                self.counts[slot] = self.counts[slot].saturating_add(1);
                self.most = self.most.max(usize::from(self.counts[slot]));
            }
            (None, Some((r, prev))) => {
                prepend(&mut self.arena[r as usize].0, &link, piece);
                self.move_first(slot, r, prev);
            }
            (Some((f, prev)), None) => {
                append(&mut self.arena[f as usize].0, &link, piece);
                self.move_first(slot, f, prev);
            }
            (Some((f, _)), Some((r, _))) => {
                // Both: the fragment joins the run in front to the one behind (cycles, or
                // fragments out of order). Unlink the one behind.
                let back = self.arena[r as usize].0;
                self.unlink(slot, r);
                let front = &mut self.arena[f as usize].0;
                append(front, &link, piece);
                (front.b, front.theta) = compose((front.b, front.theta), (back.b, back.theta));
                front.back = back.back;
                front.far = back.far;
                self.counts[slot] -= 1;
            }
        }
    }

    /// For each of `depths`, an end (near or far depth) of one of the pixel's runs within
    /// `touch` of it, or NaN: the surfaces the runs already hold there. `test` draws a face
    /// once per ray by looking for the depth of the cell before it; in per-pixel order that
    /// cell is not the one before along the ray but any run's end (docs/distributed.md).
    pub fn ends_at(&self, slot: usize, depths: [f64; 2], touch: f64) -> [f64; 2] {
        let mut found = [f64::NAN; 2];
        let mut at = self.heads[slot];
        while at != NONE {
            let (r, next) = &self.arena[at as usize];
            // A run that changes no light holds no surface (cells the ray only grazes).
            for (f, &d) in found.iter_mut().zip(&depths).filter(|_| !r.is_identity()) {
                for end in [r.near, r.far] {
                    if f.is_nan() && (end - d).abs() <= touch {
                        *f = end;
                    }
                }
            }
            at = *next;
        }
        found
    }

    /// The first run of a pixel with `pred`, and the run before it in the list.
    #[inline]
    fn find(&self, slot: usize, pred: impl Fn(&Run) -> bool) -> Option<(u32, u32)> {
        let (mut prev, mut at) = (NONE, self.heads[slot]);
        while at != NONE {
            let (r, next) = &self.arena[at as usize];
            if pred(r) {
                return Some((at, prev));
            }
            prev = at;
            at = *next;
        }
        None
    }

    #[inline]
    fn move_first(&mut self, slot: usize, at: u32, prev: u32) {
        if prev != NONE {
            self.arena[prev as usize].1 = self.arena[at as usize].1;
            self.arena[at as usize].1 = self.heads[slot];
            self.heads[slot] = at;
        }
    }

    fn unlink(&mut self, slot: usize, at: u32) {
        let next = self.arena[at as usize].1;
        if self.heads[slot] == at {
            self.heads[slot] = next;
            return;
        }
        let mut p = self.heads[slot];
        while p != NONE {
            if self.arena[p as usize].1 == at {
                self.arena[p as usize].1 = next;
                return;
            }
            p = self.arena[p as usize].1;
        }
    }

    /// The pixel's intensity over background `i0` and the volume's transparency: its runs
    /// composited back to front by depth.
    pub fn resolve(&mut self, slot: usize, i0: [f64; 3]) -> ([f64; 3], f64) {
        self.sorted.clear();
        let mut at = self.heads[slot];
        while at != NONE {
            let (r, next) = self.arena[at as usize];
            self.sorted.push(r);
            at = next;
        }
        self.sorted
            .sort_by(|a, b| by_depth((a.near, a.far), (b.near, b.far)));
        // Disjoint stretches of mesh never overlap along a ray; cells that do interpenetrate.
        let mut overlapped = false;
        for w in self.sorted.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            if overlap((a.near, a.far), (b.near, b.far)) {
                overlapped = true;
                if self.overlap_cells.len() < EXAMPLES {
                    self.overlap_cells
                        .push((a.back.min(b.front), a.back.max(b.front)));
                }
            }
        }
        self.overlaps += usize::from(overlapped);
        back_to_front(self.sorted.iter().map(|r| (r.b, r.theta)), i0)
    }

    /// The pixel's runs as [`Stretch`]es, appended to `out` in no particular order; runs that
    /// change no light (clipped away: `b = 0`, `θ = 1`) are left out. Returns how many.
    pub fn export(&self, slot: usize, out: &mut Vec<Stretch>) -> usize {
        let start = out.len();
        let mut at = self.heads[slot];
        while at != NONE {
            let (r, next) = self.arena[at as usize];
            if !r.is_identity() {
                out.push(Stretch {
                    near: r.near,
                    far: r.far,
                    b: r.b,
                    theta: r.theta,
                });
            }
            at = next;
        }
        out.len() - start
    }
}

/// One run as it leaves the tile (a distributed frame's unit of exchange,
/// docs/distributed.md): the depth interval of the ray inside one stretch of cells, and the
/// composed map `I ↦ I·θ + b` of that stretch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch {
    pub near: f64,
    pub far: f64,
    pub b: [f64; 3],
    pub theta: f64,
}

/// The order runs are composited in: by near depth, then far depth (a stable sort keeps the
/// arrival order of equal ones).
#[inline]
pub fn by_depth(a: (f64, f64), b: (f64, f64)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
}

/// Whether run `b` (sorted after `a`) starts before `a` ends by more than rounding: the cells
/// of the two interpenetrate.
#[inline]
pub fn overlap(a: (f64, f64), b: (f64, f64)) -> bool {
    let tol = OVERLAP * ((a.1 - a.0) + (b.1 - b.0) + a.1.abs());
    b.0 < a.1 - tol
}

/// Depth-sorted runs `(b, θ)` (front first) composited back to front over `i0`: the pixel's
/// intensity and the volume's transparency. The one formula for a pixel's runs, whether they
/// come from one tile or from several ranks.
#[inline]
pub fn back_to_front(
    sorted: impl DoubleEndedIterator<Item = ([f64; 3], f64)>,
    i0: [f64; 3],
) -> ([f64; 3], f64) {
    let mut acc = (i0, 1.0);
    for r in sorted.rev() {
        acc = compose(r, acc);
    }
    acc
}

/// Puts a fragment in front of a run.
#[inline]
fn prepend(run: &mut Run, link: &Link, piece: ([f64; 3], f64)) {
    (run.b, run.theta) = compose(piece, (run.b, run.theta));
    run.front = link.cell;
    run.near = link.near;
}

/// Puts a fragment behind a run.
#[inline]
fn append(run: &mut Run, link: &Link, piece: ([f64; 3], f64)) {
    (run.b, run.theta) = compose((run.b, run.theta), piece);
    run.back = link.cell;
    run.far = link.far;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::NO_NEIGHBOR;

    fn link(cell: u32, entry: u32, exit: u32, near: f64) -> Link {
        Link {
            cell,
            entry_neighbor: entry,
            exit_neighbor: exit,
            entry_earlier: entry != NO_NEIGHBOR,
            exit_earlier: exit != NO_NEIGHBOR,
            near,
            far: near + 1.0,
        }
    }

    /// Cells 0 → 1 → 2 (front to back) and, separately, 3 in front of them all: every arrival
    /// order gives the composition in depth order.
    #[test]
    fn any_arrival_order_gives_the_order_along_the_ray() {
        let n = NO_NEIGHBOR;
        let frags = [
            (link(0, n, 1, 1.0), ([0.1, 0.0, 0.0], 0.9)),
            (link(1, 0, 2, 2.0), ([0.0, 0.2, 0.0], 0.5)),
            (link(2, 1, n, 3.0), ([0.0, 0.0, 0.3], 0.7)),
            (link(3, n, n, -5.0), ([0.05, 0.05, 0.05], 0.8)),
        ];
        // Back to front by hand: 2, 1, 0, 3 over white.
        let mut want = ([1.0; 3], 1.0);
        for k in [2, 1, 0, 3] {
            want = compose(frags[k].1, want);
        }
        let perms = [
            [0, 1, 2, 3],
            [3, 2, 1, 0],
            [2, 0, 1, 3],
            [1, 3, 0, 2],
            [0, 2, 3, 1],
        ];
        for p in perms {
            let mut runs = Runs::new(1);
            for (i, &k) in p.iter().enumerate() {
                // As the renderer does: only neighbours that already arrived are searched.
                let arrived = |c: u32| p[..i].iter().any(|&j| frags[j].0.cell == c);
                let mut l = frags[k].0;
                l.entry_earlier = arrived(l.entry_neighbor);
                l.exit_earlier = arrived(l.exit_neighbor);
                runs.add(0, l, frags[k].1);
            }
            let got = runs.resolve(0, [1.0; 3]);
            for c in 0..3 {
                assert!((got.0[c] - want.0[c]).abs() < 1e-15, "{p:?}");
            }
            assert!((got.1 - want.1).abs() < 1e-15);
        }
    }
}
