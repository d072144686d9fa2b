//! MPVO: a topological sort of the "is behind" relation across interior faces, decided by exact
//! orientation predicates so that both cells of a face always agree.

use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicU8, Ordering::Relaxed};

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
const QUEUED: u8 = 1 << 7;

#[inline]
fn behind_count(state: u8) -> u8 {
    (state >> 4) & 7
}

/// The relation for every cell, in parallel, each cell's byte made by `wrap` (plain for the
/// serial sort, atomic for the parallel one). Both cells of a face evaluate the same exact
/// predicate (with the face's nodes in opposite orders), so they always agree.
fn relation<T: Send>(input: &SortInput, wrap: fn(u8) -> T) -> Vec<T> {
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
            wrap(state)
        })
        .collect()
}

/// Depth of a cell's centroid (distance from the eye, or −z for orthographic views).
fn depth(input: &SortInput, cell: usize) -> f64 {
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

/// A queue of cells that are ready to be placed: FIFO for MPVO, farthest-first for MPVONC.
trait Ready {
    fn push(&mut self, cell: u32, input: &SortInput);
    fn pop(&mut self) -> Option<u32>;
    /// Whether the queue keeps every cell it ever held, in the order they were popped (a
    /// FIFO's own contents are the order): then the sort need not record it.
    const KEEPS_ORDER: bool;
    /// That order, for a queue that keeps it.
    fn into_order(self) -> Vec<u32>;
}

/// First in, first out: the serial MPVO the parallel one is tested against.
#[cfg(test)]
struct Fifo {
    cells: Vec<u32>,
    next: usize,
}

#[cfg(test)]
impl Ready for Fifo {
    const KEEPS_ORDER: bool = true;
    fn push(&mut self, cell: u32, _: &SortInput) {
        self.cells.push(cell);
    }
    fn pop(&mut self) -> Option<u32> {
        let c = self.cells.get(self.next).copied();
        self.next += usize::from(c.is_some());
        c
    }
    fn into_order(self) -> Vec<u32> {
        self.cells
    }
}

/// Max-heap on (depth, −index): the farthest ready cell first, ties by index.
#[derive(PartialEq)]
struct Far(f64, u32);
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

impl Ready for BinaryHeap<Far> {
    const KEEPS_ORDER: bool = false;
    fn push(&mut self, cell: u32, input: &SortInput) {
        BinaryHeap::push(self, Far(depth(input, cell as usize), cell));
    }
    fn pop(&mut self) -> Option<u32> {
        BinaryHeap::pop(self).map(|f| f.1)
    }
    fn into_order(self) -> Vec<u32> {
        unreachable!("a heap does not keep the order")
    }
}

/// Kahn's algorithm over the relation. A cell is queued once: when its last neighbour behind
/// it has been placed, or — when the queue runs dry with cells left, a visibility cycle — as
/// the farthest cell still waiting, which is counted.
fn topological<Q: Ready>(input: &SortInput, mut ready: Q) -> Order {
    let n = input.mesh.tet_count();
    let nbs = input.mesh.neighbors();
    let mut state = relation(input, |s| s);
    let enqueue = |c: usize, state: &mut [u8], ready: &mut Q| {
        state[c] |= QUEUED;
        ready.push(c as u32, input);
    };
    for c in 0..n {
        if behind_count(state[c]) == 0 {
            enqueue(c, &mut state, &mut ready);
        }
    }
    // A FIFO holds the order itself; a heap's pops are recorded.
    let mut order = Vec::with_capacity(if Q::KEEPS_ORDER { 0 } else { n });
    let mut placed = 0;
    let mut cycle_cells = 0;
    loop {
        while let Some(c) = ready.pop() {
            let c = c as usize;
            placed += 1;
            if !Q::KEEPS_ORDER {
                order.push(c as u32);
            }
            let front = state[c] & 0xF;
            for f in 0..4 {
                if front & (1 << f) != 0 {
                    let m = nbs[c][f] as usize;
                    if behind_count(state[m]) > 0 {
                        state[m] -= BEHIND;
                    }
                    if behind_count(state[m]) == 0 && state[m] & QUEUED == 0 {
                        enqueue(m, &mut state, &mut ready);
                    }
                }
            }
        }
        if placed == n {
            break;
        }
        let Some(c) = (0..n)
            .filter(|&c| state[c] & QUEUED == 0)
            .max_by(|&a, &b| depth(input, a).total_cmp(&depth(input, b)).then(b.cmp(&a)))
        else {
            break;
        };
        cycle_cells += 1;
        enqueue(c, &mut state, &mut ready);
    }
    Order {
        back_to_front: if Q::KEEPS_ORDER {
            ready.into_order()
        } else {
            order
        },
        cycle_cells,
    }
}

/// MPVO on every core: Kahn's algorithm a level at a time. A level is every cell whose
/// neighbours behind it have all been placed in earlier levels; a large level's cells release
/// their neighbours in front in parallel (an atomic count per cell, so each newly ready cell is
/// taken by exactly one thread), a small one's on the calling thread — which is then exactly
/// the serial FIFO sort.
///
/// Which cells form each level depends on the mesh and the view alone; the order inside a
/// level released in parallel depends on the threads' timing, and that changes no image: the
/// cells a ray crosses are chained by faces, each behind the next, so they lie in different
/// levels, and every pixel composites its cells in the one order the levels give (per-pixel
/// runs, where a frame keeps them, compare a cell only with the neighbours across the faces a
/// ray crosses, which lie in other levels too). Thus a valid MPVO order, the same image bit
/// for bit with any number of threads.
fn mpvo(input: &SortInput) -> Order {
    levels(input, PARALLEL_LEVEL).0
}

/// [`mpvo`], releasing levels of at least `parallel_level` cells in parallel; also where each
/// level ends in the order.
fn levels(input: &SortInput, parallel_level: usize) -> (Order, Vec<usize>) {
    let n = input.mesh.tet_count();
    let nbs = input.mesh.neighbors();
    let state = relation(input, AtomicU8::new);
    // The order is its own queue: a level is a stretch of it, its successors are appended.
    let mut order: Vec<u32> = (0..n as u32)
        .into_par_iter()
        .with_min_len(4096)
        .filter(|&c| {
            let s = &state[c as usize];
            let ready = behind_count(s.load(Relaxed)) == 0;
            if ready {
                s.fetch_or(QUEUED, Relaxed);
            }
            ready
        })
        .collect();
    order.reserve_exact(n - order.len());
    let mut ends = Vec::new();
    let mut cycle_cells = 0;
    let parallel = rayon::current_num_threads() > 1;
    let mut start = 0;
    loop {
        while start < order.len() {
            let end = order.len();
            if end - start < parallel_level || !parallel {
                for i in start..end {
                    let c = order[i];
                    release::<false>(c, nbs, &state, &mut order);
                }
            } else {
                let next: Vec<u32> = order[start..end]
                    .par_chunks(LEVEL_CHUNK)
                    .flat_map_iter(|chunk| {
                        let mut next = Vec::new();
                        for &c in chunk {
                            release::<true>(c, nbs, &state, &mut next);
                        }
                        next
                    })
                    .collect();
                order.extend_from_slice(&next);
            }
            ends.push(end);
            start = end;
        }
        if order.len() == n {
            break;
        }
        // A visibility cycle: the farthest cell still waiting goes next, as in `topological`.
        let Some(c) = (0..n)
            .into_par_iter()
            .filter(|&c| state[c].load(Relaxed) & QUEUED == 0)
            .max_by(|&a, &b| depth(input, a).total_cmp(&depth(input, b)).then(b.cmp(&a)))
        else {
            break;
        };
        cycle_cells += 1;
        state[c].fetch_or(QUEUED, Relaxed);
        order.push(c as u32);
    }
    let order = Order {
        back_to_front: order,
        cycle_cells,
    };
    (order, ends)
}

/// Levels with fewer cells than this are released on the calling thread: below it the handing
/// out of work costs more than it saves.
const PARALLEL_LEVEL: usize = 1024;

/// Cells of a level per parallel task.
const LEVEL_CHUNK: usize = 256;

/// Places cell `c`: each neighbour in front of it loses one waiting neighbour behind it, and
/// one that has none left (and was not forced out of a cycle) is pushed to `next`. With
/// `SHARED` (other threads place other cells of the level) by exactly one caller, as the
/// count's last decrement and the queued bit are one atomic update; without, the caller is
/// alone and plain loads and stores do.
#[inline]
fn release<const SHARED: bool>(c: u32, nbs: &[[u32; 4]], state: &[AtomicU8], next: &mut Vec<u32>) {
    let placed = |s: u8| {
        let s = if behind_count(s) > 0 { s - BEHIND } else { s };
        if behind_count(s) == 0 { s | QUEUED } else { s }
    };
    let front = state[c as usize].load(Relaxed) & 0xF;
    for f in 0..4 {
        if front & (1 << f) == 0 {
            continue;
        }
        let m = nbs[c as usize][f];
        let cell = &state[m as usize];
        let old = if SHARED {
            match cell.fetch_update(Relaxed, Relaxed, |s| Some(placed(s))) {
                Ok(old) | Err(old) => old,
            }
        } else {
            let old = cell.load(Relaxed);
            cell.store(placed(old), Relaxed);
            old
        };
        if old & QUEUED == 0 && behind_count(old) <= 1 {
            next.push(m);
        }
    }
}

fn mpvonc(input: &SortInput) -> Order {
    topological(input, BinaryHeap::with_capacity(1024))
}

/// Serial MPVO (a FIFO queue), the reference of the tests.
#[cfg(test)]
fn mpvo_serial(input: &SortInput) -> Order {
    let cells = Vec::with_capacity(input.mesh.tet_count());
    topological(input, Fifo { cells, next: 0 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::TetMesh;
    use crate::mesh::generate::kuhn_box;
    use crate::sort::SortInput;

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

    #[test]
    fn mpvo_orders_a_jittered_box_for_many_views() {
        let (nodes, tets) = kuhn_box([5, 4, 3], [1.0; 3], 0.12, 9);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        let mut rng = crate::mesh::generate::SplitMix64(5);
        for k in 0..20 {
            let r = crate::scene::Affine::rotation(
                [rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64()],
                360.0 * rng.next_f64(),
            )
            .unwrap();
            let shift = if k % 2 == 0 {
                [0.0, 0.0, -4.0]
            } else {
                [0.0; 3]
            };
            let eye_nodes: Vec<[f64; 3]> = mesh
                .nodes()
                .iter()
                .map(|&p| {
                    let q = r.apply([p[0] - 0.5, p[1] - 0.5, p[2] - 0.5]);
                    [q[0] + shift[0], q[1] + shift[1], q[2] + shift[2]]
                })
                .collect();
            let screen: Vec<[f64; 2]> = eye_nodes
                .iter()
                .map(|p| {
                    if k % 2 == 0 {
                        [p[0] / -p[2], -p[1] / -p[2]]
                    } else {
                        [p[0], -p[1]]
                    }
                })
                .collect();
            let input = SortInput {
                mesh: &mesh,
                eye_nodes: &eye_nodes,
                screen: &screen,
                perspective: k % 2 == 0,
                mirrored: false,
            };
            for s in [mpvo, mpvonc] {
                let o = s(&input);
                assert_eq!(o.cycle_cells, 0);
                assert_valid(&input, &o.back_to_front);
            }
        }
    }

    /// A box seen from a view whose screen positions are scrambled: the relation is then no
    /// projection, full of cycles, and exercises every path of the level-parallel sort.
    fn scrambled(mesh: &TetMesh, seed: u64) -> (Vec<[f64; 3]>, Vec<[f64; 2]>) {
        let mut rng = crate::mesh::generate::SplitMix64(seed);
        let eye: Vec<[f64; 3]> = mesh
            .nodes()
            .iter()
            .map(|p| [p[0], p[1], p[2] - 3.0])
            .collect();
        let screen = eye
            .iter()
            .map(|p| [p[0] + 0.1 * rng.next_f64(), -p[1] + 0.1 * rng.next_f64()])
            .collect();
        (eye, screen)
    }

    /// The level-parallel order is a valid MPVO order; released on one thread it is the serial
    /// FIFO sort's order exactly; released in parallel, in pools of 1 to 3 threads, its levels
    /// hold the same cells (only the order inside a level may change, which no pixel sees); and
    /// it breaks the same visibility cycles as the serial sort (the cells placed before each
    /// break are the same set, whatever order a Kahn sort takes them in).
    #[test]
    fn parallel_mpvo_is_valid_and_independent_of_threads() {
        let (nodes, tets) = kuhn_box([9, 8, 7], [1.0; 3], 0.12, 3);
        let mesh = TetMesh::new(nodes, tets).unwrap();
        let pools = [1, 2, 3].map(|t| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .unwrap()
        });
        for (k, scramble) in [(0u64, false), (1, false), (2, true), (3, true)] {
            let r =
                crate::scene::Affine::rotation([1.0, 0.4 * k as f64, 0.3], 17.0 + 40.0 * k as f64)
                    .unwrap();
            let (eye_nodes, screen) = if scramble {
                scrambled(&mesh, k)
            } else {
                let eye: Vec<[f64; 3]> = mesh
                    .nodes()
                    .iter()
                    .map(|&p| {
                        let q = r.apply([p[0] - 0.5, p[1] - 0.5, p[2] - 0.5]);
                        [q[0], q[1], q[2] - 4.0]
                    })
                    .collect();
                let screen = eye.iter().map(|p| [p[0], -p[1]]).collect();
                (eye, screen)
            };
            let input = SortInput {
                mesh: &mesh,
                eye_nodes: &eye_nodes,
                screen: &screen,
                perspective: false,
                mirrored: false,
            };
            let serial = mpvo_serial(&input);
            let (reference, ends) = levels(&input, usize::MAX);
            assert_eq!(reference, serial, "one thread: the FIFO sort's order");
            if scramble {
                assert!(serial.cycle_cells > 0, "the scrambled view has cycles");
            } else {
                assert_eq!(serial.cycle_cells, 0);
                assert_valid(&input, &reference.back_to_front);
            }
            let level_sets = |order: &[u32], ends: &[usize]| {
                let mut start = 0;
                ends.iter()
                    .map(|&end| {
                        let mut level = order[start..end].to_vec();
                        level.sort_unstable();
                        start = end;
                        level
                    })
                    .collect::<Vec<_>>()
            };
            let expected = level_sets(&reference.back_to_front, &ends);
            for pool in &pools {
                for parallel_level in [1, 64, usize::MAX] {
                    let (o, e) = pool.install(|| levels(&input, parallel_level));
                    assert_eq!(o.cycle_cells, reference.cycle_cells);
                    assert_eq!(level_sets(&o.back_to_front, &e), expected);
                    if !scramble {
                        assert_valid(&input, &o.back_to_front);
                    }
                }
            }
        }
    }
}
