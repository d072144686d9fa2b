//! MPVO: a topological sort of the "is behind" relation across interior faces, decided by exact
//! orientation predicates so that both cells of a face always agree.

use std::collections::{BinaryHeap, VecDeque};

use super::{Order, SortInfo, SortInput};
use crate::mesh::{FACE_NODES, NO_NEIGHBOR, orientation};

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
fn facing(input: &SortInput, cell: usize, f: usize) -> i8 {
    let tet = input.mesh.tets()[cell];
    let [a, b, c] = FACE_NODES[f].map(|k| input.eye_nodes[tet[k] as usize]);
    let s = if input.perspective {
        orientation(a, b, c, [0.0; 3])
    } else {
        // The viewer at +∞ z: the sign of the outward normal's z component.
        robust::orient2d(
            robust::Coord { x: a[0], y: a[1] },
            robust::Coord { x: b[0], y: b[1] },
            robust::Coord { x: c[0], y: c[1] },
        )
    };
    if s > 0.0 {
        1
    } else if s < 0.0 {
        -1
    } else {
        0
    }
}

/// For each cell: the bit mask of faces whose neighbour is in front, and the number of
/// neighbours behind it.
fn relation(input: &SortInput) -> (Vec<u8>, Vec<u8>) {
    let n = input.mesh.tet_count();
    let mut front = vec![0u8; n];
    let mut behind = vec![0u8; n];
    for (cell, nb) in input.mesh.neighbors().iter().enumerate() {
        for f in 0..4 {
            if nb[f] == NO_NEIGHBOR {
                continue;
            }
            match facing(input, cell, f) {
                1 => front[cell] |= 1 << f,
                -1 => behind[cell] += 1,
                _ => {}
            }
        }
    }
    (front, behind)
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

/// A ready queue: FIFO for MPVO, farthest-first for MPVONC.
trait Ready {
    fn push(&mut self, cell: u32, input: &SortInput);
    fn pop(&mut self) -> Option<u32>;
}

impl Ready for VecDeque<u32> {
    fn push(&mut self, cell: u32, _: &SortInput) {
        self.push_back(cell);
    }
    fn pop(&mut self) -> Option<u32> {
        self.pop_front()
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
    fn push(&mut self, cell: u32, input: &SortInput) {
        BinaryHeap::push(self, Far(depth(input, cell as usize), cell));
    }
    fn pop(&mut self) -> Option<u32> {
        BinaryHeap::pop(self).map(|f| f.1)
    }
}

/// Kahn's algorithm over the relation; when the queue runs dry with cells left (a cycle), the
/// farthest remaining cell is released and counted.
fn topological<Q: Ready>(input: &SortInput, mut ready: Q) -> Order {
    let n = input.mesh.tet_count();
    let (front, mut behind) = relation(input);
    for (c, &b) in behind.iter().enumerate() {
        if b == 0 {
            ready.push(c as u32, input);
        }
    }
    let mut order = Vec::with_capacity(n);
    let mut done = vec![false; n];
    let mut cycle_cells = 0;
    let nbs = input.mesh.neighbors();
    loop {
        while let Some(c) = ready.pop() {
            let c = c as usize;
            if done[c] {
                continue;
            }
            done[c] = true;
            order.push(c as u32);
            for f in 0..4 {
                if front[c] & (1 << f) != 0 {
                    let m = nbs[c][f] as usize;
                    behind[m] = behind[m].saturating_sub(1);
                    if behind[m] == 0 && !done[m] {
                        ready.push(m as u32, input);
                    }
                }
            }
        }
        if order.len() == n {
            break;
        }
        // A cycle: release the farthest cell still waiting.
        let next = (0..n)
            .filter(|&c| !done[c])
            .max_by(|&a, &b| depth(input, a).total_cmp(&depth(input, b)).then(b.cmp(&a)));
        let Some(next) = next else { break };
        cycle_cells += 1;
        behind[next] = 0;
        ready.push(next as u32, input);
    }
    Order {
        back_to_front: order,
        cycle_cells,
    }
}

fn mpvo(input: &SortInput) -> Order {
    topological(input, VecDeque::with_capacity(1024))
}

fn mpvonc(input: &SortInput) -> Order {
    topological(input, BinaryHeap::with_capacity(1024))
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
                if let Some(n) = input.mesh.neighbor(c, f) {
                    if facing(input, c, f) == 1 {
                        assert!(pos[c] < pos[n], "cell {c} is behind {n} but drawn after it");
                    }
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
            let input = SortInput {
                mesh: &mesh,
                eye_nodes: &eye_nodes,
                perspective: k % 2 == 0,
            };
            for s in [mpvo, mpvonc] {
                let o = s(&input);
                assert_eq!(o.cycle_cells, 0);
                assert_valid(&input, &o.back_to_front);
            }
        }
    }
}
