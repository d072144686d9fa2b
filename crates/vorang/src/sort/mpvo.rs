//! MPVO: a topological sort of the "is behind" relation across interior faces, decided by exact
//! orientation predicates so that both cells of a face always agree.

use rayon::prelude::*;

use super::{Order, SortInfo, SortInput};
use crate::mesh::{FACE_NODES, NO_NEIGHBOR, orientation};
use crate::predicates::{entry_sign, orient_sign};

pub const MPVO: SortInfo = SortInfo {
    name: "mpvo",
    summary: "Williams' MPVO: exact for connected convex meshes",
    sort: mpvo,
};

pub const MPVONC: SortInfo = SortInfo {
    name: "mpvonc",
    summary: "MPVO with depth priority among ready cells (Williams' MPVONC heuristic) for meshes with concavities or holes",
    sort: mpvonc,
};

/// +1 if the viewer is on the outer side of face `f` of `cell` (the neighbour across it is in
/// front), −1 if on the inner side, 0 if exactly in its plane.
#[cfg(test)]
fn facing(input: &SortInput, cell: usize, f: usize) -> i8 {
    let corners = input.mesh.gather(cell, input.eye_nodes);
    let screen = input.mesh.gather(cell, input.screen);
    face_sign(&corners, &screen, f, input)
}

/// [`facing`] for a cell whose corners (in eye space and on screen) are at hand.
#[inline]
fn face_sign(p: &[[f64; 3]; 4], s: &[[f64; 2]; 4], f: usize, input: &SortInput) -> i8 {
    let [i, j, k] = FACE_NODES[f];
    if !input.perspective || (p[i][2] < 0.0 && p[j][2] < 0.0 && p[k][2] < 0.0) {
        // An entry face of the cell (render/faces.rs): the viewer is on its outer side.
        return orient_sign(s[i], s[j], s[k]) * entry_sign(input.mirrored);
    }
    // A node at or behind the eye has no screen position: the eye's side of the plane.
    let o = orientation(p[i], p[j], p[k], [0.0; 3]);
    let o = if input.mirrored { -o } else { o };
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// Per cell, packed in one byte so that the sort touches one array: bits 0–3 the faces whose
/// neighbour is in front, bits 4–6 the number of neighbours behind it not yet placed, bit 7
/// whether it has been queued.
const BEHIND: u8 = 1 << 4;
pub(super) const QUEUED: u8 = 1 << 7;

#[inline]
pub(super) fn behind_count(state: u8) -> u8 {
    (state >> 4) & 7
}

/// One fewer neighbour behind the cell of byte `state` is waiting; whether the cell is now
/// ready (and is marked queued).
#[inline]
pub(super) fn release(state: &mut u8) -> bool {
    let s = *state;
    // A cell queued out of a cycle may still be counting down; it never counts below zero.
    let s = if behind_count(s) > 0 { s - BEHIND } else { s };
    let ready = behind_count(s) == 0 && s & QUEUED == 0;
    *state = if ready { s | QUEUED } else { s };
    ready
}

/// The relation for every cell, in parallel. Both cells of a face evaluate the same exact
/// predicate (with the face's nodes in opposite orders), so they always agree.
pub(super) fn relation(input: &SortInput) -> Vec<u8> {
    let nbs = input.mesh.neighbors();
    (0..input.mesh.tet_count())
        .into_par_iter()
        .with_min_len(4096)
        .map(|cell| {
            let p = input.mesh.gather(cell, input.eye_nodes);
            let s = input.mesh.gather(cell, input.screen);
            let mut state = 0u8;
            for f in 0..4 {
                if nbs[cell][f] == NO_NEIGHBOR {
                    continue;
                }
                match face_sign(&p, &s, f, input) {
                    1 => state |= 1 << f,
                    -1 => state += BEHIND,
                    _ => {}
                }
            }
            state
        })
        .collect()
}

/// Depth of a cell's centroid (distance from the eye, or −z for orthographic views).
pub(super) fn depth(input: &SortInput, cell: usize) -> f64 {
    let tet = input.mesh.tets()[cell];
    let c = [0, 1, 2].map(|k| {
        tet.iter()
            .map(|&n| input.eye_nodes[n as usize][k])
            .sum::<f64>()
            * 0.25
    });
    if input.perspective {
        (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
    } else {
        -c[2]
    }
}

/// Max-heap on (depth, −index): the farthest ready cell first, ties by index.
#[derive(PartialEq)]
pub(super) struct Far(pub f64, pub u32);
impl Eq for Far {}
impl PartialOrd for Far {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Far {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0).then(o.1.cmp(&self.1))
    }
}

/// The farthest cell among those `waiting` (ties: the lowest number): where a visibility cycle
/// is broken.
pub(super) fn farthest_waiting(
    input: &SortInput,
    waiting: impl Fn(usize) -> bool + Sync,
) -> Option<usize> {
    // On every core: the comparison orders all cells (ties by number), so the result does not
    // depend on how the search is split.
    (0..input.mesh.tet_count())
        .into_par_iter()
        .with_min_len(1 << 14)
        .filter(|&c| waiting(c))
        .max_by(|&a, &b| depth(input, a).total_cmp(&depth(input, b)).then(b.cmp(&a)))
}

/// Cells per thread of the sort at least (the order is the same on any number of threads).
const CELLS_PER_THREAD: usize = 1 << 15;

/// The threads of a sort by levels of `cells` cells: more threads than cores would wait for
/// each other at every level, and a thread needs enough cells to be worth its start and its
/// meetings.
pub(super) fn sort_threads(cells: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    rayon::current_num_threads()
        .min(cores)
        .min(cells / CELLS_PER_THREAD)
        .max(1)
}

/// MPVO: Kahn's algorithm over the relation, a level at a time on every core
/// ([`super::levels`]).
fn mpvo(input: &SortInput) -> Order {
    let threads = sort_threads(input.mesh.tet_count());
    let mut nothing = vec![(); input.mesh.tet_count()];
    super::levels::by_levels(
        input,
        &mut relation(input),
        &mut nothing,
        |_| (),
        threads,
        true,
    )
    .into_order()
}

/// MPVONC: Kahn's algorithm with the farthest ready cell first. A cell is queued once: when its
/// last neighbour behind it has been placed, or — when no cell is ready with cells left, a
/// visibility cycle — as the farthest cell still waiting, which is counted. Computed on every
/// core as a sort by bound ([`super::farthest`]).
fn mpvonc(input: &SortInput) -> Order {
    super::farthest::farthest_first(input, relation(input))
}

#[cfg(test)]
pub(super) mod tests {
    use std::collections::BinaryHeap;

    use super::*;
    use crate::mesh::TetMesh;
    use crate::mesh::generate::kuhn_box;
    use crate::sort::SortInput;

    /// MPVONC's order one cell at a time, with a heap: what [`super::super::farthest`]
    /// computes on every core, kept as the reference its tests compare with.
    pub(crate) fn mpvonc_serial(input: &SortInput, mut state: Vec<u8>) -> Order {
        let n = input.mesh.tet_count();
        let nbs = input.mesh.neighbors();
        let mut ready = BinaryHeap::with_capacity(1024);
        let enqueue = |c: usize, state: &mut [u8], ready: &mut BinaryHeap<Far>| {
            state[c] |= QUEUED;
            ready.push(Far(depth(input, c), c as u32));
        };
        for c in 0..n {
            if behind_count(state[c]) == 0 {
                enqueue(c, &mut state, &mut ready);
            }
        }
        let mut order = Vec::with_capacity(n);
        let mut cycle_cells = 0;
        loop {
            while let Some(Far(_, c)) = ready.pop() {
                let c = c as usize;
                order.push(c as u32);
                let front = state[c] & 0xF;
                for f in 0..4 {
                    if front & (1 << f) != 0 {
                        let m = nbs[c][f] as usize;
                        if release(&mut state[m]) {
                            ready.push(Far(depth(input, m), m as u32));
                        }
                    }
                }
            }
            if order.len() == n {
                break;
            }
            let Some(c) = farthest_waiting(input, |c| state[c] & QUEUED == 0) else {
                break;
            };
            cycle_cells += 1;
            enqueue(c, &mut state, &mut ready);
        }
        Order {
            back_to_front: order,
            cycle_cells,
        }
    }

    /// Every interior face: the cell behind it comes first.
    pub(crate) fn assert_valid(input: &SortInput, order: &[u32]) {
        let mut pos = vec![usize::MAX; input.mesh.tet_count()];
        for (i, &c) in order.iter().enumerate() {
            pos[c as usize] = i;
        }
        assert!(pos.iter().all(|&p| p != usize::MAX), "every cell appears");
        for c in 0..input.mesh.tet_count() {
            for f in 0..4 {
                if let Some(n) = input.mesh.neighbor(c, f)
                    && facing(input, c, f) == 1
                {
                    assert!(pos[c] < pos[n], "cell {c} is behind {n} but drawn after it");
                }
            }
        }
    }

    /// `count` views of `mesh` (which lies in the unit cube), turned at random from `seed`:
    /// eye-space nodes, screen positions and whether the view is perspective (every other one,
    /// with the eye at `distance` from the centre).
    pub(crate) fn views(
        mesh: &TetMesh,
        seed: u64,
        count: usize,
        distance: f64,
    ) -> impl Iterator<Item = (Vec<[f64; 3]>, Vec<[f64; 2]>, bool)> + '_ {
        let mut rng = crate::mesh::generate::SplitMix64(seed);
        (0..count).map(move |k| {
            let r = crate::scene::Affine::rotation(
                [rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64()],
                360.0 * rng.next_f64(),
            )
            .unwrap();
            let perspective = k % 2 == 0;
            let eye: Vec<[f64; 3]> = mesh
                .nodes()
                .iter()
                .map(|&p| {
                    let q = r.apply([p[0] - 0.5, p[1] - 0.5, p[2] - 0.5]);
                    [q[0], q[1], q[2] - if perspective { distance } else { 0.0 }]
                })
                .collect();
            let screen = eye
                .iter()
                .map(|p| {
                    if perspective {
                        [p[0] / -p[2], -p[1] / -p[2]]
                    } else {
                        [p[0], -p[1]]
                    }
                })
                .collect();
            (eye, screen, perspective)
        })
    }

    #[test]
    fn mpvo_orders_a_jittered_box_for_many_views() {
        let (nodes, tets) = kuhn_box([5, 4, 3], [1.0; 3], 0.12, 9);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        for (eye_nodes, screen, perspective) in views(&mesh, 5, 20, 4.0) {
            let input = SortInput {
                mesh: &mesh,
                eye_nodes: &eye_nodes,
                screen: &screen,
                perspective,
                mirrored: false,
            };
            for s in [mpvo, mpvonc] {
                let o = s(&input);
                assert_eq!(o.cycle_cells, 0);
                assert_valid(&input, &o.back_to_front);
            }
        }
    }
}
