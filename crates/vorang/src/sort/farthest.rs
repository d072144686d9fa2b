//! MPVONC's order on every core: Kahn's sort that always places the farthest ready cell next
//! (Williams' heuristic for meshes with concavities or holes, the thesis's `VRxConcaveSort`,
//! 5.2.1), computed without its one-cell-at-a-time priority queue and with the same result.
//!
//! A cell's *key* is its centroid's depth (farther first; ties go to the lower cell number, as in
//! the queue). Its *bound* is the least depth among the cell and every cell behind it through
//! chains of faces: `bound(v) = min(depth(v), bound(u) for every neighbour u behind v)`. The
//! queue's order is the cells sorted by bound, greatest first, where the cells of one bound (a
//! *run*) keep the queue's own order among themselves. Why: say the order so built places a
//! cell `c` of bound `d` next, every cell of a greater bound already placed. A ready cell `x`
//! (all its cells behind placed) outside the run has a lesser bound; its cells behind are
//! placed, so their bounds are at least `d`, and `x`'s bound is then its own depth — less than
//! `d`, which no cell of the run is nearer than. The cells of the run that are ready are those
//! whose cells behind in the run are placed, and the queue run inside the run picks the
//! farthest of them. So every step places the farthest ready cell: the queue's choice, and
//! with distinct keys its order is the only one that does.
//!
//! Every part of that runs in parallel: the bounds travel with the sort by levels, each placed
//! cell telling the cells in front of it its bound ([`super::levels`]); then the sort by bound,
//! and the runs, which are small (mostly one cell, or a cell and one farther cell in front of
//! it). A visibility cycle splits the order into phases: the queue and the levels both run dry
//! when every cell they can reach is placed, and then force out the same cell, the farthest one
//! waiting. It starts the next phase: the cells still waiting forget the bounds they were told
//! before, and the forced cell is ready in its run, whatever its cells behind (which the queue
//! ignores once it is placed).
//!
//! The bounds are kept as 32-bit floats, to hold 4 bytes per cell instead of 8 at the frame's
//! busiest moment. Rounding is monotone, so the bound of the rounded depths is the rounded
//! bound, and the cells whose bounds round alike form one run: the consecutive runs of the
//! order above, merged. The argument holds for the merged runs as it is: a ready cell outside
//! one rounds nearer than every cell in it, so it is nearer.

use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::levels::{Carry, by_levels};
use super::mpvo::{Far, depth, sort_threads};
use super::{Order, SortInput};

/// A cell's bound (a depth, rounded), as the sort by levels carries it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Bound(f32);

impl Carry for Bound {
    /// The nearer depth.
    #[inline]
    fn take(&mut self, from: Bound) {
        if from.0.total_cmp(&self.0).is_lt() {
            *self = from;
        }
    }
}

/// MPVONC's order over the relation `state` ([`super::mpvo::relation`]).
pub(super) fn farthest_first(input: &SortInput, state: Vec<u8>) -> Order {
    rounded_farthest_first(input, state, |d| d as f32)
}

/// [`farthest_first`] with the bounds rounded by `round` (monotone: the tests round coarsely).
fn rounded_farthest_first(
    input: &SortInput,
    mut state: Vec<u8>,
    round: impl Fn(f64) -> f32 + Sync,
) -> Order {
    let n = input.mesh.tet_count();
    let own = |c| Bound(round(depth(input, c)));
    let mut bounds: Vec<Bound> = (0..n).into_par_iter().with_min_len(4096).map(own).collect();
    let fresh = own;
    let levelled = by_levels(
        input,
        &mut state,
        &mut bounds,
        fresh,
        sort_threads(n),
        false,
    );
    let starts = &levelled.starts;
    // The phases: where each starts, and the cell forced out of a cycle that starts it.
    let mut phases: Vec<(usize, Option<u32>)> = vec![(0, None)];
    for &level in &levelled.forced {
        // A forced level holds one cell: only the first can start where the order does.
        let start = starts[level as usize];
        if start == 0 {
            phases.clear();
        }
        phases.push((start, Some(levelled.order[start])));
    }
    let mut order = levelled.order;
    let runs = Runs {
        input,
        nbs: input.mesh.neighbors(),
        state: &state,
        bounds: &bounds,
    };
    for (k, &(start, forced)) in phases.iter().enumerate() {
        let end = phases.get(k + 1).map_or(n, |p| p.0);
        runs.sort(&mut order[start..end], forced);
    }
    Order {
        back_to_front: order,
        cycle_cells: levelled.forced.len(),
    }
}

/// What the runs are settled with.
struct Runs<'a> {
    input: &'a SortInput<'a>,
    nbs: &'a [[u32; 4]],
    /// The relation: bits 0–3 the faces with a neighbour in front.
    state: &'a [u8],
    /// Each cell's bound in its phase.
    bounds: &'a [Bound],
}

impl Runs<'_> {
    /// Whether `u` is a neighbour behind `v`: `u` has `v` in front (a face seen edge-on, with
    /// neither in front, counts for neither).
    #[inline]
    fn is_behind(&self, u: u32, v: u32) -> bool {
        let front = self.state[u as usize];
        (0..4).any(|g| front & (1 << g) != 0 && self.nbs[u as usize][g] == v)
    }

    /// One phase's cells in the queue's order: by bound, greatest first, each run in its own
    /// order; `forced` starts the phase.
    fn sort(&self, cells: &mut [u32], forced: Option<u32>) {
        // The cells themselves are sorted, their keys looked up: sorting (key, cell) pairs took
        // as long and held 12 bytes more per cell at the frame's busiest moment.
        let key = |c: &u32| descending(self.bounds[*c as usize].0.into());
        cells.par_sort_unstable_by_key(key);
        let forced = forced.unwrap_or(u32::MAX);
        cells
            .par_chunk_by_mut(|a, b| key(a) == key(b))
            .for_each(|run| {
                if run.len() > 1 {
                    self.settle(run, forced);
                }
            });
    }

    /// A run's cells in the queue's order: the farthest cell whose cells behind in the run are
    /// placed (`forced` is ready from the start).
    fn settle(&self, run: &mut [u32], forced: u32) {
        if let [a, b] = run {
            // Most runs of two: a cell and the farther cell in front of it, which comes after.
            let (x, y) = (*a, *b);
            let (x_behind, y_behind) = (self.is_behind(x, y), self.is_behind(y, x));
            let x_first = if x == forced || y == forced {
                x == forced
            } else if x_behind || y_behind {
                x_behind
            } else {
                Far(depth(self.input, x as usize), x) > Far(depth(self.input, y as usize), y)
            };
            (*a, *b) = if x_first { (x, y) } else { (y, x) };
            return;
        }
        let mut members = run.to_vec();
        members.sort_unstable();
        let mut waiting = vec![0u8; members.len()];
        let in_front = |u: u32| {
            let front = self.state[u as usize];
            (0..4)
                .filter(move |f| front & (1 << f) != 0)
                .map(move |f| self.nbs[u as usize][f])
                .filter(move |&m| m != forced)
                .filter_map(|m| members.binary_search(&m).ok())
        };
        for &u in &members {
            for j in in_front(u) {
                waiting[j] += 1;
            }
        }
        let key = |c: u32| Far(depth(self.input, c as usize), c);
        let mut ready: BinaryHeap<Far> = (0..members.len())
            .filter(|&j| waiting[j] == 0)
            .map(|j| key(members[j]))
            .collect();
        let mut placed = 0;
        while let Some(Far(_, c)) = ready.pop() {
            run[placed] = c;
            placed += 1;
            for j in in_front(c) {
                waiting[j] -= 1;
                if waiting[j] == 0 {
                    ready.push(key(members[j]));
                }
            }
        }
        debug_assert_eq!(placed, run.len(), "a run's cells wait only for each other");
    }
}

/// A depth as an integer that orders as [`f64::total_cmp`] does, reversed: the farthest first.
#[inline]
fn descending(d: f64) -> u64 {
    let bits = d.to_bits() as i64;
    let total = bits ^ ((((bits >> 63) as u64) >> 1) as i64);
    !((total as u64) ^ (1 << 63))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TetMesh;
    use crate::mesh::generate::{SplitMix64, kuhn_box};
    use crate::sort::levels::tests::{random_relation, turned_box};
    use crate::sort::mpvo::relation;
    use crate::sort::mpvo::tests::mpvonc_serial;
    use crate::sort::mpvo::tests::views;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    impl<'a> SortInput<'a> {
        fn orthographic(mesh: &'a TetMesh, eye: &'a [[f64; 3]], screen: &'a [[f64; 2]]) -> Self {
            SortInput {
                mesh,
                eye_nodes: eye,
                screen,
                perspective: false,
                mirrored: false,
            }
        }
    }

    /// The queue's order, on 1, 2 and 3 threads, and with the bounds rounded coarsely (runs
    /// merged: a 64th of the unit cube's depth).
    fn check(input: &SortInput, state: Vec<u8>) -> usize {
        let want = mpvonc_serial(input, state.clone());
        for threads in [1, 2, 3] {
            let got = pool(threads).install(|| farthest_first(input, state.clone()));
            assert_eq!(got, want, "{threads} threads");
        }
        let coarse = |d: f64| (d * 64.0).floor() as f32;
        let got = pool(2).install(|| rounded_farthest_first(input, state.clone(), coarse));
        assert_eq!(got, want, "rounded coarsely");
        want.cycle_cells
    }

    #[test]
    fn descending_orders_as_total_cmp_reversed() {
        let xs = [
            f64::NEG_INFINITY,
            -3.5,
            -1e-300,
            -0.0,
            0.0,
            1e-300,
            2.0,
            2.0000000000000004,
            f64::INFINITY,
        ];
        for a in xs {
            for b in xs {
                assert_eq!(descending(a).cmp(&descending(b)), b.total_cmp(&a));
            }
        }
    }

    /// A box with a tenth of its cells taken out (holes, tunnels: the order is not a visibility
    /// order everywhere) and the whole box, seen from many sides.
    #[test]
    fn the_queues_order_on_any_number_of_threads() {
        let (nodes, tets) = kuhn_box([13, 11, 9], [1.0; 3], 0.15, 4);
        let mut rng = SplitMix64(17);
        let holey: Vec<[u32; 4]> = tets
            .iter()
            .copied()
            .filter(|_| rng.next_f64() >= 0.1)
            .collect();
        for tets in [tets, holey] {
            let mesh = TetMesh::new(nodes.clone(), tets).unwrap();
            for (eye, screen, perspective) in views(&mesh, 23, 8, 2.5) {
                let input = SortInput {
                    mesh: &mesh,
                    eye_nodes: &eye,
                    screen: &screen,
                    perspective,
                    mirrored: false,
                };
                check(&input, relation(&input));
            }
        }
    }

    /// A grid without jitter seen straight along two of its axes: many cells
    /// exactly as deep as others (ties settled by number), faces seen edge-on; holes, cycles
    /// from faces turned at random, and a mirrored view too.
    #[test]
    fn ties_in_depth_as_the_queue_breaks_them() {
        let (nodes, tets) = kuhn_box([7, 6, 5], [1.0; 3], 0.0, 1);
        let mut rng = SplitMix64(3);
        let holey: Vec<[u32; 4]> = tets
            .iter()
            .copied()
            .filter(|_| rng.next_f64() >= 0.15)
            .collect();
        for tets in [tets, holey] {
            let mesh = TetMesh::new(nodes.clone(), tets).unwrap();
            // Along z, and along x (the axes turned exactly, by a permutation).
            for axes in [[0, 1, 2], [1, 2, 0]] {
                let eye: Vec<[f64; 3]> = mesh
                    .nodes()
                    .iter()
                    .map(|&p| axes.map(|k| p[k] - 0.5))
                    .collect();
                let screen: Vec<[f64; 2]> = eye.iter().map(|p| [p[0], -p[1]]).collect();
                let mut depths: Vec<f64> = (0..mesh.tet_count())
                    .map(|c| depth(&SortInput::orthographic(&mesh, &eye, &screen), c))
                    .collect();
                depths.sort_by(f64::total_cmp);
                depths.dedup();
                assert!(depths.len() * 4 < mesh.tet_count(), "many ties");
                for mirrored in [false, true] {
                    let input = SortInput {
                        mirrored,
                        ..SortInput::orthographic(&mesh, &eye, &screen)
                    };
                    check(&input, relation(&input));
                }
                let input = SortInput::orthographic(&mesh, &eye, &screen);
                assert!(check(&input, random_relation(&mesh, 4)) > 5);
            }
        }
    }

    /// Faces turned at random: the relation is full of cycles, broken one cell at a time, and
    /// depth says little about the order.
    #[test]
    fn cycles_split_the_order_as_the_queue_does() {
        let (mesh, eye, screen) = turned_box();
        let input = SortInput::orthographic(&mesh, &eye, &screen);
        for seed in [8, 9, 10] {
            let state = random_relation(&mesh, seed);
            assert!(check(&input, state) > 10, "cycles were broken");
        }
        // Every cell as deep as every other (the view flattened): one run per phase, which
        // holds the cell forced out of a cycle, ready whatever its cells behind in the run.
        let flat: Vec<[f64; 3]> = eye.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let input = SortInput::orthographic(&mesh, &flat, &screen);
        for seed in [8, 9] {
            assert!(check(&input, random_relation(&mesh, seed)) > 10);
        }
    }
}
