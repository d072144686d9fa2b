//! Visibility exact per pixel for any mesh: per-pixel *runs* of cells chained through their
//! shared faces (SPEC §4; DESIGN §8 "order exact per pixel").
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

use crate::mesh::NO_NEIGHBOR;

/// Where a fragment lies along its ray: its cell, the cells across its entry and exit faces
/// ([`NO_NEIGHBOR`] at the mesh boundary or where it is clipped), and its depth interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    pub cell: u32,
    pub entry_neighbor: u32,
    pub exit_neighbor: u32,
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

/// The runs of every pixel of a tile.
#[derive(Debug, Default)]
pub struct Runs {
    pixels: Vec<Vec<Run>>,
    /// The most runs any pixel held (memory report).
    pub most: usize,
}

impl Runs {
    pub fn new(pixels: usize) -> Runs {
        Runs {
            pixels: (0..pixels).map(|_| Vec::new()).collect(),
            most: 0,
        }
    }

    /// Adds fragment `link` with contribution `piece` (`I ↦ I·θ + b`) to pixel `slot`.
    pub fn add(&mut self, slot: usize, link: Link, piece: ([f64; 3], f64)) {
        let runs = &mut self.pixels[slot];
        let behind = (link.exit_neighbor != NO_NEIGHBOR)
            .then(|| runs.iter().position(|r| r.front == link.exit_neighbor))
            .flatten();
        let before = (link.entry_neighbor != NO_NEIGHBOR)
            .then(|| runs.iter().position(|r| r.back == link.entry_neighbor))
            .flatten();
        match (before, behind) {
            (None, None) => {
                runs.push(Run {
                    b: piece.0,
                    theta: piece.1,
                    front: link.cell,
                    back: link.cell,
                    near: link.near,
                    far: link.far,
                });
                self.most = self.most.max(runs.len());
            }
            (None, Some(r)) => {
                let run = &mut runs[r];
                (run.b, run.theta) = compose(piece, (run.b, run.theta));
                run.front = link.cell;
                run.near = link.near;
            }
            (Some(s), None) => {
                let run = &mut runs[s];
                (run.b, run.theta) = compose((run.b, run.theta), piece);
                run.back = link.cell;
                run.far = link.far;
            }
            (Some(s), Some(r)) => {
                let back = runs[r];
                let front = &mut runs[s];
                let map = compose(compose((front.b, front.theta), piece), (back.b, back.theta));
                (front.b, front.theta) = map;
                front.back = back.back;
                front.far = back.far;
                runs.swap_remove(r);
            }
        }
    }

    /// The pixel's intensity over background `i0` and the volume's transparency: its runs
    /// composited back to front by depth.
    pub fn resolve(&mut self, slot: usize, i0: [f64; 3]) -> ([f64; 3], f64) {
        let runs = &mut self.pixels[slot];
        runs.sort_by(|a, b| a.near.total_cmp(&b.near).then(a.far.total_cmp(&b.far)));
        let mut acc = (i0, 1.0);
        for r in runs.iter().rev() {
            let (i, t) = acc;
            acc = (
                [
                    i[0] * r.theta + r.b[0],
                    i[1] * r.theta + r.b[1],
                    i[2] * r.theta + r.b[2],
                ],
                t * r.theta,
            );
        }
        runs.clear();
        acc
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn link(cell: u32, entry: u32, exit: u32, near: f64) -> Link {
        Link {
            cell,
            entry_neighbor: entry,
            exit_neighbor: exit,
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
            for k in p {
                runs.add(0, frags[k].0, frags[k].1);
            }
            let got = runs.resolve(0, [1.0; 3]);
            for c in 0..3 {
                assert!((got.0[c] - want.0[c]).abs() < 1e-15, "{p:?}");
            }
            assert!((got.1 - want.1).abs() < 1e-15);
        }
    }
}
