//! MPVONC's order on every core: Kahn's sort that always places the farthest ready cell next
//! (Williams' heuristic for meshes with concavities or holes, the thesis's `VRxConcaveSort`,
//! 5.2.1), computed without its one-cell-at-a-time priority queue and with the same result.
//!
//! Give every cell the *key* of its centroid's depth (farther is greater, ties broken by the
//! lower cell number, as the queue breaks them). A cell's *bound* is the least key among the
//! cell and every cell behind it through chains of faces: `bound(v) = min(key(v), bound(u) for
//! every neighbour u behind v)`, and the cell whose key it is, its *root*. The queue's order is
//! the cells sorted by bound, greatest first, where the cells of one root (a group: the root and
//! the farther cells it holds back) keep the queue's own order among themselves. Why: say the
//! order so built places a cell `c` of root `r` next, every cell of a greater bound already
//! placed. A ready cell `x` (all its cells behind placed) of another group has a lesser bound;
//! its cells behind are placed, so their bounds are at least `key(r)`, and `x`'s bound is then
//! its own key — less than `key(r)`, which no cell of `r`'s group is below. Among the ready cells
//! of `r`'s group the queue run inside the group picks the farthest. So every step places the
//! farthest ready cell: the queue's choice, and with distinct keys its order is the only one
//! that does.
//!
//! Every part of that runs in parallel: the bounds travel with the sort by levels, each placed
//! cell telling the cells in front of it its bound ([`super::levels`]); then the sort by bound,
//! and the groups, which are small (mostly a cell and one farther cell in front of it). A
//! visibility cycle splits the order into phases: the queue and the levels both run dry when
//! every cell they can reach is placed, and then force out the same cell, the farthest one
//! waiting. It starts the next phase alone: the cells still waiting forget the bounds they were
//! told before, and the forced cell is a group of its own (every other cell of the phase is
//! nearer, and its cells behind that come later are ignored, by the queue as here).

use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::levels::{Carry, by_levels};
use super::mpvo::{Far, depth, sort_threads};
use super::{Order, SortInput};

/// A cell's bound: its root's depth and number.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bound {
    depth: f64,
    root: u32,
}

impl Bound {
    /// A cell's own key.
    fn of(input: &SortInput, cell: usize) -> Bound {
        Bound {
            depth: depth(input, cell),
            root: cell as u32,
        }
    }
}

impl Carry for Bound {
    /// The lesser key: nearer, or as near with a greater number.
    #[inline]
    fn take(&mut self, from: Bound) {
        if from
            .depth
            .total_cmp(&self.depth)
            .then(self.root.cmp(&from.root))
            .is_lt()
        {
            *self = from;
        }
    }
}

/// MPVONC's order over the relation `state` ([`super::mpvo::relation`]).
pub(super) fn farthest_first(input: &SortInput, mut state: Vec<u8>) -> Order {
    let n = input.mesh.tet_count();
    let mut bounds: Vec<Bound> = (0..n)
        .into_par_iter()
        .with_min_len(4096)
        .map(|c| Bound::of(input, c))
        .collect();
    let fresh = |c| Bound::of(input, c);
    let levelled = by_levels(input, &mut state, &mut bounds, fresh, sort_threads(n));
    let groups = Groups {
        input,
        nbs: input.mesh.neighbors(),
        state: &state,
        bounds: &bounds,
    };
    let mut order = levelled.order;
    let starts = &levelled.starts;
    // The phases: from the start, and from each forced cell's level.
    let mut phases = vec![0];
    phases.extend(levelled.forced.iter().map(|&l| starts[l as usize]));
    phases.dedup();
    phases.push(n);
    for phase in phases.windows(2) {
        groups.sort(&mut order[phase[0]..phase[1]]);
    }
    Order {
        back_to_front: order,
        cycle_cells: levelled.forced.len(),
    }
}

/// What the groups are made of.
struct Groups<'a> {
    input: &'a SortInput<'a>,
    nbs: &'a [[u32; 4]],
    /// The relation: bits 0–3 the faces with a neighbour in front.
    state: &'a [u8],
    /// Each cell's bound within its phase.
    bounds: &'a [Bound],
}

impl Groups<'_> {
    /// One phase's cells, which have their bounds, in the queue's order: by bound, greatest
    /// first, each group in its own order.
    fn sort(&self, cells: &mut [u32]) {
        // (bound's depth as a descending integer, root, cell): one sort key for the bound.
        let mut items: Vec<(u64, u32, u32)> = cells
            .par_iter()
            .with_min_len(4096)
            .map(|&c| {
                let b = self.bounds[c as usize];
                (descending(b.depth), b.root, c)
            })
            .collect();
        items.par_sort_unstable_by_key(|&(d, r, _)| (d, r));
        items.par_chunk_by_mut(|a, b| a.1 == b.1).for_each(|group| {
            if group.len() > 1 {
                self.settle(group);
            }
        });
        cells
            .par_iter_mut()
            .with_min_len(4096)
            .zip(items.par_iter())
            .for_each(|(c, it)| *c = it.2);
    }

    /// A group's cells in the queue's order: from the root, the farthest cell whose cells
    /// behind in the group are placed.
    fn settle(&self, group: &mut [(u64, u32, u32)]) {
        let root = group[0].1;
        if let [a, b] = group {
            // Most groups: a root and one cell it holds back, which comes after it.
            (a.2, b.2) = (root, if a.2 == root { b.2 } else { a.2 });
            return;
        }
        let mut members: Vec<u32> = group.iter().map(|it| it.2).collect();
        members.sort_unstable();
        let mut waiting = vec![0u8; members.len()];
        let in_front = |u: u32| {
            let front = self.state[u as usize];
            (0..4)
                .filter(move |f| front & (1 << f) != 0)
                .map(move |f| self.nbs[u as usize][f])
                .filter_map(|m| members.binary_search(&m).ok())
        };
        for &u in &members {
            for j in in_front(u) {
                waiting[j] += 1;
            }
        }
        let key = |c: u32| Far(depth(self.input, c as usize), c);
        let mut ready = BinaryHeap::from([key(root)]);
        let mut placed = 0;
        while let Some(Far(_, c)) = ready.pop() {
            group[placed].2 = c;
            placed += 1;
            for j in in_front(c) {
                waiting[j] -= 1;
                if waiting[j] == 0 {
                    ready.push(key(members[j]));
                }
            }
        }
        debug_assert_eq!(placed, group.len(), "a group is reached from its root");
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
    use crate::sort::mpvo::relation;
    use crate::sort::mpvo::tests::mpvonc_serial;
    use crate::sort::mpvo::tests::views;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    /// The queue's order, on 1, 2 and 3 threads.
    fn check(input: &SortInput, state: Vec<u8>) -> usize {
        let want = mpvonc_serial(input, state.clone());
        for threads in [1, 2, 3] {
            let got = pool(threads).install(|| farthest_first(input, state.clone()));
            assert_eq!(got, want, "{threads} threads");
        }
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

    /// Faces turned at random: the relation is full of cycles, broken one cell at a time, and
    /// the groups are large (depth says little about the order).
    #[test]
    fn cycles_split_the_order_as_the_queue_does() {
        let (nodes, tets) = kuhn_box([9, 8, 7], [1.0; 3], 0.1, 5);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        let (eye, screen, _) = views(&mesh, 2, 2, 3.0).nth(1).unwrap();
        let input = SortInput {
            mesh: &mesh,
            eye_nodes: &eye,
            screen: &screen,
            perspective: false,
            mirrored: false,
        };
        for seed in [8, 9, 10] {
            let state = crate::sort::levels::tests::random_relation(&mesh, seed);
            assert!(check(&input, state) > 10, "cycles were broken");
        }
    }
}
