//! Face adjacency in linear time.
//!
//! Every face is keyed by its sorted node triple `(a < b < c)`. A counting sort on the smallest
//! node `a` puts the faces of each node into one small bucket (≈ 24 faces per node in a typical
//! mesh), and sorting each bucket by `(b, c)` makes matching faces adjacent. This avoids a hash
//! map or a global sort of 4·n keys and runs in one pass over memory; the buckets are matched
//! in parallel.

use rayon::prelude::*;

use super::{MeshError, NO_NEIGHBOR};

/// Nodes whose buckets one parallel task matches (a few hundred thousand faces).
const NODES_PER_TASK: usize = 1 << 14;

/// The counting sort's passes over the cells run in at most this many parts (each part counts
/// into a table as long as the nodes).
const PARTS: usize = 4;
/// Cells per part at least.
const CELLS_PER_PART: usize = 1 << 16;

/// Marks a place of a bucket that holds no matched face after [`match_buckets`].
const UNMATCHED: u32 = u32::MAX;

/// Matches the faces of the buckets of `nodes`, whose face ids `ids` holds (the buckets one
/// after another, `start` as for all nodes): each bucket's slots are overwritten with its
/// matched faces as consecutive pairs, then [`UNMATCHED`]. Fails on the first face shared by
/// more than two cells.
fn match_buckets(
    tets: &[[u32; 4]],
    start: &[u32],
    ids: &mut [u32],
    nodes: std::ops::Range<usize>,
) -> Result<(), MeshError> {
    let base = start[nodes.start] as usize;
    let mut bucket: Vec<(u64, u32)> = Vec::with_capacity(64);
    for a in nodes {
        let slots = &mut ids[start[a] as usize - base..start[a + 1] as usize - base];
        bucket.clear();
        bucket.extend(slots.iter().map(|&id| {
            let (t, f) = (id as usize / 4, id as usize % 4);
            let [_, b, c] = sorted_face(&tets[t], f);
            ((u64::from(b) << 32) | u64::from(c), id)
        }));
        bucket.sort_unstable();
        slots.fill(UNMATCHED);
        let mut written = 0;
        let mut i = 0;
        while i < bucket.len() {
            let mut j = i + 1;
            while j < bucket.len() && bucket[j].0 == bucket[i].0 {
                j += 1;
            }
            match j - i {
                1 => {}
                2 => {
                    slots[written] = bucket[i].1;
                    slots[written + 1] = bucket[i + 1].1;
                    written += 2;
                }
                _ => {
                    let mut ids: Vec<usize> =
                        bucket[i..j].iter().map(|&(_, id)| id as usize).collect();
                    ids.sort_unstable();
                    let third = ids[2];
                    return Err(MeshError::NonManifold {
                        tet: third / 4,
                        face: third % 4,
                        others: [ids[0] / 4, ids[1] / 4],
                    });
                }
            }
            i = j;
        }
    }
    Ok(())
}

/// For each cell and face `i` (opposite node `i`): the neighbouring cell or [`NO_NEIGHBOR`].
/// Fails if a face is shared by more than two cells.
///
/// Memory: besides the result, one face id per face (the buckets), which the matching then
/// overwrites in place with the matched pairs — no list of pairs is built, so loading a mesh
/// peaks at the buckets plus the result (docs/formats.md).
pub fn face_neighbors(node_count: usize, tets: &[[u32; 4]]) -> Result<Vec<[u32; 4]>, MeshError> {
    let faces = tets.len() * 4;
    if faces > UNMATCHED as usize {
        return Err(MeshError::TooLarge { tets: tets.len() });
    }
    // Count faces per smallest node, each part of the cells on its own, in parallel.
    let parts = rayon::current_num_threads()
        .clamp(1, PARTS)
        .min(tets.len().div_ceil(CELLS_PER_PART).max(1));
    let per_part = tets.len().div_ceil(parts).max(1);
    let mut fill: Vec<Vec<u32>> = tets
        .par_chunks(per_part)
        .map(|part| {
            let mut count = vec![0u32; node_count];
            for tet in part {
                for f in 0..4 {
                    count[min_node_except(tet, f) as usize] += 1;
                }
            }
            count
        })
        .collect();
    // Where each bucket starts, and where in it each part writes: after the parts before it,
    // so that a bucket holds its faces in cell order, as one pass over the cells would.
    let mut start = vec![0u32; node_count + 1];
    let mut total = 0u32;
    for a in 0..node_count {
        start[a] = total;
        for part in fill.iter_mut() {
            let count = part[a];
            part[a] = total;
            total += count;
        }
    }
    start[node_count] = total;
    // Scatter face ids (cell·4 + face) into their buckets, the parts in parallel.
    let mut order = vec![0u32; faces];
    let slots = Slots(order.as_mut_ptr(), faces);
    tets.par_chunks(per_part)
        .zip(fill.par_iter_mut())
        .enumerate()
        .for_each(|(p, (part, fill))| {
            for (i, tet) in part.iter().enumerate() {
                for f in 0..4 {
                    let a = min_node_except(tet, f) as usize;
                    // SAFETY: part p's faces of node a go to its own stretch of a's bucket,
                    // `fill[a]` counting through it (the sums above), so every place of
                    // `order` is written once, by one part.
                    unsafe { slots.put(fill[a] as usize, ((p * per_part + i) * 4 + f) as u32) };
                    fill[a] += 1;
                }
            }
        });
    drop(fill);

    // Each node's bucket is matched on its own, so the buckets are matched in parallel, in
    // chunks of nodes, each chunk owning its buckets' stretch of `order`. The chunks' results
    // come back in node order, so the first error reported is the one a single thread would
    // find first.
    let mut chunks: Vec<(std::ops::Range<usize>, &mut [u32])> = Vec::new();
    let mut bounds = Vec::new();
    let mut rest: &mut [u32] = &mut order;
    for first in (0..node_count).step_by(NODES_PER_TASK) {
        let last = (first + NODES_PER_TASK).min(node_count);
        bounds.push(start[first] as usize..start[last] as usize);
        let (mine, after) = rest.split_at_mut((start[last] - start[first]) as usize);
        chunks.push((first..last, mine));
        rest = after;
    }
    let matched: Vec<Result<(), MeshError>> = chunks
        .into_par_iter()
        .map(|(nodes, ids)| match_buckets(tets, &start, ids, nodes))
        .collect();
    matched.into_iter().collect::<Result<(), MeshError>>()?;
    drop(start);
    // Every bucket begins with its pairs, so the matched faces of each chunk of buckets pair up
    // in the order they stand; the chunks in parallel.
    let mut neighbors = vec![[NO_NEIGHBOR; 4]; tets.len()];
    let sides = Slots(neighbors.as_mut_ptr().cast::<u32>(), tets.len() * 4);
    bounds.par_iter().for_each(|range| {
        let mut matched = order[range.clone()].iter().filter(|&&id| id != UNMATCHED);
        while let (Some(&p), Some(&q)) = (matched.next(), matched.next()) {
            // SAFETY: place `id` of the neighbour table is cell id / 4, face id % 4; every face
            // id stands once in `order`, so every place is written once, by one chunk.
            unsafe {
                sides.put(p as usize, q / 4);
                sides.put(q as usize, p / 4);
            }
        }
    });
    Ok(neighbors)
}

/// A table that parallel passes write in places they own alone (each place once).
struct Slots(*mut u32, usize);

// SAFETY: the writers of a `Slots` write disjoint places (see each use).
unsafe impl Sync for Slots {}

impl Slots {
    /// Writes `value` at place `i`.
    ///
    /// # Safety
    /// No other thread reads or writes place `i` during the pass.
    #[inline]
    unsafe fn put(&self, i: usize, value: u32) {
        assert!(i < self.1, "a place of the table");
        // SAFETY: `i` is in bounds; the caller owns the place.
        unsafe { self.0.add(i).write(value) };
    }
}

#[inline]
fn min_node_except(tet: &[u32; 4], f: usize) -> u32 {
    let mut m = u32::MAX;
    for (k, &n) in tet.iter().enumerate() {
        if k != f && n < m {
            m = n;
        }
    }
    m
}

#[inline]
fn sorted_face(tet: &[u32; 4], f: usize) -> [u32; 3] {
    let mut v = [0u32; 3];
    let mut k = 0;
    for (i, &n) in tet.iter().enumerate() {
        if i != f {
            v[k] = n;
            k += 1;
        }
    }
    if v[0] > v[1] {
        v.swap(0, 1);
    }
    if v[1] > v[2] {
        v.swap(1, 2);
    }
    if v[0] > v[1] {
        v.swap(0, 1);
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_tets_sharing_a_face() {
        let tets = [[0, 1, 2, 3], [4, 1, 2, 3]];
        let nb = face_neighbors(5, &tets).unwrap();
        assert_eq!(nb[0], [1, NO_NEIGHBOR, NO_NEIGHBOR, NO_NEIGHBOR]);
        assert_eq!(nb[1], [0, NO_NEIGHBOR, NO_NEIGHBOR, NO_NEIGHBOR]);
    }

    #[test]
    fn three_tets_on_one_face_fail_naming_the_third() {
        let tets = [[0, 1, 2, 3], [4, 1, 2, 3], [5, 3, 2, 1]];
        let e = face_neighbors(6, &tets).unwrap_err();
        assert_eq!(
            e,
            MeshError::NonManifold {
                tet: 2,
                face: 0,
                others: [0, 1]
            }
        );
    }

    /// The parallel matching (several tasks of nodes) against a plain hash map of faces.
    #[test]
    fn matches_a_hash_map_of_faces_across_tasks() {
        let vol = crate::volume::jittered_box(300_000, 0.1, 3);
        let tets = vol.mesh.tets();
        assert!(vol.mesh.node_count() > 2 * NODES_PER_TASK, "several tasks");
        let nb = face_neighbors(vol.mesh.node_count(), tets).unwrap();
        let mut faces: std::collections::HashMap<[u32; 3], Vec<usize>> = Default::default();
        for (t, tet) in tets.iter().enumerate() {
            for f in 0..4 {
                faces
                    .entry(sorted_face(tet, f))
                    .or_default()
                    .push(t * 4 + f);
            }
        }
        let mut expected = vec![[NO_NEIGHBOR; 4]; tets.len()];
        for ids in faces.values() {
            if let [p, q] = ids[..] {
                expected[p / 4][p % 4] = (q / 4) as u32;
                expected[q / 4][q % 4] = (p / 4) as u32;
            }
        }
        assert_eq!(nb, expected);
    }
}
