//! Which cells each rank holds, and a rank's cells as a volume of their own
//! (docs/distributed.md, "Pieces and ranks").
//!
//! A parallel writer's `.pvtu` lists its pieces; with no more ranks than pieces, rank r of n
//! takes the contiguous range of pieces `⌊r·P/n⌋ … ⌊(r+1)·P/n⌋`; with more ranks than pieces,
//! piece p goes to the ranks `⌊p·n/P⌋ … ⌊(p+1)·n/P⌋`, which split its cells in the Morton order
//! of their centroids. Any other file is one piece.
//!
//! Two ranks holding the two cells of a face must compute the same depths on it, bit for bit,
//! so that their runs meet without gap or overlap. The renderer computes a face's depth from its
//! nodes in ascending node number ([`crate::render::faces`]), so a rank's piece numbers its
//! nodes in an order every rank agrees on ([`NodeKey`]): the `GlobalNodeIds` point array where
//! the file has one; the node numbers of the file where every rank reads the same file (one
//! piece); else the coordinates, bit for bit — equal coordinates are equal on screen, so their
//! order does not matter.

use std::cmp::Ordering;
use std::ops::Range;

use crate::data::ElementKind;
use crate::error::Error;
use crate::field::Interpolator;
use crate::mesh::Aabb;
use crate::volume::{Volume, select};

/// The name of the point array that numbers the nodes of all pieces alike (VTK's
/// `vtkGlobalIds` as ParaView writes them).
pub const GLOBAL_NODE_IDS: &str = "GlobalNodeIds";

/// What one rank holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Share {
    /// These pieces, whole.
    Pieces(Range<usize>),
    /// Part `part` (of `parts`) of piece `piece`, by the Morton order of its cells.
    Part {
        piece: usize,
        part: usize,
        parts: usize,
    },
}

/// Rank `rank`'s share of `pieces` pieces among `ranks` ranks.
pub fn share(pieces: usize, rank: usize, ranks: usize) -> Share {
    let ranks = ranks.max(1);
    if ranks <= pieces {
        return Share::Pieces(rank * pieces / ranks..(rank + 1) * pieces / ranks);
    }
    // Each piece has at least one rank: ⌊(p+1)·n/P⌋ − ⌊p·n/P⌋ ≥ 1 when n > P.
    let first = |p: usize| p * ranks / pieces.max(1);
    let piece = (0..pieces.max(1)).rfind(|&p| first(p) <= rank).unwrap_or(0);
    Share::Part {
        piece,
        part: rank - first(piece),
        parts: first(piece + 1) - first(piece),
    }
}

/// Part `part` of `parts` of the cells `tets` of `vol`: the cells sorted by the Morton code of
/// their centroids (21 bits per axis over the centroids' box; equal codes by cell number), cut
/// into `parts` runs of equal length; returned in ascending cell order.
pub fn morton_part(vol: &Volume, tets: &[u32], part: usize, parts: usize) -> Vec<u32> {
    let centroids: Vec<[f64; 3]> = tets
        .iter()
        .map(|&t| {
            let c = vol.mesh.corners(t as usize);
            [0, 1, 2].map(|k| 0.25 * (c[0][k] + c[1][k] + c[2][k] + c[3][k]))
        })
        .collect();
    let b = Aabb::of_points(&centroids);
    const TOP: f64 = ((1u64 << 21) - 1) as f64;
    let mut keyed: Vec<(u64, u32)> = centroids
        .iter()
        .zip(tets)
        .map(|(c, &t)| {
            let q = [0, 1, 2].map(|k| {
                let span = b.max[k] - b.min[k];
                if span > 0.0 {
                    ((c[k] - b.min[k]) / span * TOP).clamp(0.0, TOP) as u64
                } else {
                    0
                }
            });
            (morton(q), t)
        })
        .collect();
    keyed.sort_unstable();
    let n = keyed.len();
    let parts = parts.max(1);
    let mut out: Vec<u32> = keyed[part * n / parts..(part + 1) * n / parts]
        .iter()
        .map(|k| k.1)
        .collect();
    out.sort_unstable();
    out
}

/// Interleaves the low 21 bits of x, y, z (x lowest).
fn morton(q: [u64; 3]) -> u64 {
    let spread = |mut v: u64| {
        v &= (1 << 21) - 1;
        v = (v | v << 32) & 0x001f_0000_0000_ffff;
        v = (v | v << 16) & 0x001f_0000_ff00_00ff;
        v = (v | v << 8) & 0x100f_00f0_0f00_f00f;
        v = (v | v << 4) & 0x10c3_0c30_c30c_30c3;
        (v | v << 2) & 0x1249_2492_4924_9249
    };
    spread(q[0]) | spread(q[1]) << 1 | spread(q[2]) << 2
}

/// The order every rank numbers its nodes in.
#[derive(Debug, Clone, PartialEq)]
pub enum NodeKey {
    /// The file's node numbers (every rank read the same file).
    Numbers,
    /// The `GlobalNodeIds` point array, per node.
    Ids(Vec<f64>),
    /// The coordinates, x then y then z, as ordered by `f64::total_cmp`.
    Coordinates,
}

impl NodeKey {
    /// The key of `vol`: its `GlobalNodeIds` where it has them (a scalar node array); the node
    /// numbers where the file is one piece; else the coordinates.
    pub fn of(vol: &Volume, one_piece: bool) -> NodeKey {
        let ids = vol.data.fields.iter().find(|f| {
            f.name.as_deref() == Some(GLOBAL_NODE_IDS)
                && f.interpolator == Interpolator::Linear
                && f.is_scalar()
        });
        if let Some(f) = ids {
            let raw = &vol.data.raw[f.sources[0]];
            if raw.kind == ElementKind::Node {
                return NodeKey::Ids((0..raw.elements()).map(|n| raw.value(n, 0)).collect());
            }
        }
        if one_piece {
            NodeKey::Numbers
        } else {
            NodeKey::Coordinates
        }
    }

    /// Compares two nodes of `vol` by the key.
    fn compare(&self, vol: &Volume, a: u32, b: u32) -> Ordering {
        match self {
            NodeKey::Numbers => a.cmp(&b),
            NodeKey::Ids(ids) => ids[a as usize].total_cmp(&ids[b as usize]),
            NodeKey::Coordinates => {
                let (p, q) = (vol.mesh.nodes()[a as usize], vol.mesh.nodes()[b as usize]);
                p[0].total_cmp(&q[0])
                    .then(p[1].total_cmp(&q[1]))
                    .then(p[2].total_cmp(&q[2]))
            }
        }
    }
}

/// The cells `tets` of `vol` as a volume of their own: the nodes they use numbered in `key`'s
/// order, with the bounding box `bbox` (the whole's: a piece is centred and framed as the
/// whole).
pub fn piece(vol: &Volume, tets: Vec<u32>, key: &NodeKey, bbox: Aabb) -> Result<Volume, Error> {
    let order = |a: u32, b: u32| key.compare(vol, a, b);
    let mut out = match key {
        NodeKey::Numbers => select(vol, tets, None)?,
        _ => select(vol, tets, Some(&order))?,
    };
    std::sync::Arc::make_mut(&mut out.mesh).set_bbox(bbox);
    Ok(out)
}

/// The tets of `vol` that rank `rank` of `ranks` holds, where `pieces` lists each piece's tets
/// (a whole volume cut into pieces in memory, as the tests cut it; a rank reading a `.pvtu`
/// reads only its own pieces, [`super::load`]).
pub fn rank_tets(vol: &Volume, pieces: &[Vec<u32>], rank: usize, ranks: usize) -> Vec<u32> {
    match share(pieces.len(), rank, ranks) {
        Share::Pieces(range) => {
            let mut tets: Vec<u32> = pieces[range].concat();
            tets.sort_unstable();
            tets
        }
        Share::Part { piece, part, parts } => morton_part(vol, &pieces[piece], part, parts),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_of_pieces_and_parts_of_pieces() {
        assert_eq!(share(4, 0, 2), Share::Pieces(0..2));
        assert_eq!(share(4, 1, 2), Share::Pieces(2..4));
        assert_eq!(share(5, 2, 3), Share::Pieces(3..5));
        assert_eq!(share(1, 0, 1), Share::Pieces(0..1));
        let parts: Vec<Share> = (0..5).map(|r| share(2, r, 5)).collect();
        let part = |piece, part, parts| Share::Part { piece, part, parts };
        assert_eq!(
            parts,
            [
                part(0, 0, 2),
                part(0, 1, 2),
                part(1, 0, 3),
                part(1, 1, 3),
                part(1, 2, 3)
            ]
        );
        assert_eq!(share(1, 3, 4), part(0, 3, 4));
    }

    #[test]
    fn morton_codes_interleave_bits() {
        assert_eq!(morton([1, 0, 0]), 1);
        assert_eq!(morton([0, 1, 0]), 2);
        assert_eq!(morton([0, 0, 1]), 4);
        assert_eq!(morton([3, 0, 0]), 0b1001);
        let top = (1 << 21) - 1;
        assert_eq!(morton([top, top, top]), (1 << 63) - 1);
    }

    #[test]
    fn morton_parts_cover_the_cells_once() {
        let vol = crate::volume::jittered_box(600, 0.1, 3);
        let all: Vec<u32> = (0..vol.mesh.tet_count() as u32).collect();
        let mut seen: Vec<u32> = (0..3).flat_map(|p| morton_part(&vol, &all, p, 3)).collect();
        seen.sort_unstable();
        assert_eq!(seen, all);
    }
}
