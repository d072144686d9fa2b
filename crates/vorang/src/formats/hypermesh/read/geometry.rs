//! Resolving the geometry: every coding of triangles (by nodes, by edges) and tetrahedra (by
//! nodes, triangles or edges) becomes node indices, codings given together are cross-checked,
//! and the primary coding (Nodes, Triangles, Edges, the first given) makes the mesh. Kept
//! apart from reading because it works on values, whatever the encoding, and from the data
//! because fields need the finished mesh; each coding is a function of its own since each has
//! its own rule for what a valid row is.

use super::super::ascii::{RowLines, element_noun};
use super::super::header::{BlockDecl, Header, Target, TetCoding, TriangleCoding};
use super::{Block, Geometry, NONE, edge_index, edges_of_cells};
use crate::data::Values;
use crate::error::{ParseError, Warning};
use crate::mesh::{EDGE_NODES, TetMesh};

/// A geometry block's values, taken out of the block list, with what is needed to report
/// errors on its rows. The values are released once converted, to keep peak memory low.
struct Located<'a> {
    file: &'a str,
    decl: &'a BlockDecl,
    values: Values,
    rows: Option<RowLines>,
    marker_line: usize,
}

impl Located<'_> {
    fn row_error(&self, row: usize, msg: impl std::fmt::Display) -> ParseError {
        let noun = element_noun(&self.decl.target.describe());
        match &self.rows {
            Some(rows) => ParseError::new(
                self.file,
                rows.line_of(row).unwrap_or(self.marker_line),
                format!("{noun} {}: {msg}", row + 1),
            ),
            None => ParseError::new(
                self.file,
                self.marker_line,
                format!("{noun} {} of block @{}: {msg}", row + 1, self.decl.marker),
            ),
        }
    }

    fn elements(&self) -> usize {
        self.values.len() / self.decl.ty.numbers().max(1)
    }

    /// Frees the values (after conversion); row positions stay for messages.
    fn release(&mut self) {
        self.values = Values::U8(Vec::new());
    }

    /// The rows as 0-based index tuples, each entry in 1…`max` (or 0 → [`NONE`] if `allow_zero`).
    /// Releases the values.
    fn indices<const N: usize>(
        &mut self,
        max: usize,
        of: &str,
        allow_zero: bool,
    ) -> Result<Vec<[u32; N]>, ParseError> {
        let v = &self.values;
        let mut out = Vec::with_capacity(self.elements());
        for e in 0..self.elements() {
            let mut row = [0u32; N];
            for (k, slot) in row.iter_mut().enumerate() {
                let x = v.get_int(e * N + k).unwrap_or(-1);
                *slot = if x == 0 && allow_zero {
                    NONE
                } else if x >= 1 && x as u64 <= max as u64 {
                    (x - 1) as u32
                } else if x == 0 {
                    return Err(self.row_error(
                        e,
                        format!("index 0 is not a valid {of} (indices are 1-based: 1…{max})"),
                    ));
                } else {
                    return Err(
                        self.row_error(e, format!("{of} index {x} is out of range 1…{max}"))
                    );
                };
            }
            out.push(row);
        }
        self.release();
        Ok(out)
    }
}

fn distinct<const N: usize>(loc: &Located, rows: &[[u32; N]], of: &str) -> Result<(), ParseError> {
    for (e, r) in rows.iter().enumerate() {
        for k in 1..N {
            if r[..k].contains(&r[k]) {
                return Err(loc.row_error(
                    e,
                    format!(
                        "{of} {} appears twice; expected {N} distinct {of}s",
                        r[k] + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn sorted<const N: usize>(mut a: [u32; N]) -> [u32; N] {
    a.sort_unstable();
    a
}

fn show_nodes(a: &[u32]) -> String {
    a.iter()
        .map(|n| (n + 1).to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Takes geometry blocks out of the block list, each as a [`Located`].
struct Take<'a, 'b> {
    file: &'a str,
    header: &'a Header,
    blocks: &'b mut [Option<Block>],
}

impl<'a> Take<'a, '_> {
    /// The block declared for `t`, if the file has one.
    fn located(&mut self, t: Target) -> Option<Located<'a>> {
        let header = self.header;
        let i = header.blocks.iter().position(|b| b.target == t)?;
        let b = self.blocks[i].as_mut()?;
        Some(Located {
            file: self.file,
            decl: &header.blocks[i],
            values: std::mem::replace(&mut b.values, Values::U8(Vec::new())),
            rows: b.rows.clone(),
            marker_line: b.marker_line,
        })
    }
}

/// The edge list (with its block), where the file has one.
type Edges<'a> = Option<(Vec<[u32; 2]>, Located<'a>)>;

/// Triangles of each coding given, as node indices, with their blocks.
type TriangleCodings<'a> = Vec<(Vec<[u32; 3]>, Located<'a>)>;

pub(super) fn resolve_geometry(
    file: &str,
    header: &Header,
    blocks: &mut [Option<Block>],
    warnings: &mut Vec<Warning>,
) -> Result<Option<Geometry>, ParseError> {
    let mut take = Take {
        file,
        header,
        blocks,
    };
    let mut tet_blocks: Vec<(TetCoding, Located)> =
        [TetCoding::Nodes, TetCoding::Triangles, TetCoding::Edges]
            .into_iter()
            .filter_map(|c| Some((c, take.located(Target::Tetrahedra(c))?)))
            .collect();
    let Some(primary_line) = tet_blocks.first().map(|(_, l)| l.decl.line) else {
        return Ok(None);
    };
    let Some(mut node_loc) = take.located(Target::Nodes) else {
        return Err(ParseError::new(
            file,
            primary_line,
            "Tetrahedra need node coordinates: expected 'Nodes { double[3] Coordinates } = @…'",
        ));
    };
    let coord_type = node_loc.decl.ty.scalar;
    let nodes: Vec<[f64; 3]> = (0..node_loc.elements())
        .map(|e| [0, 1, 2].map(|k| node_loc.values.get(3 * e + k)))
        .collect();
    node_loc.release();
    let n_nodes = nodes.len();

    let edges: Edges = match take.located(Target::Edges) {
        Some(mut l) => {
            let e = l.indices::<2>(n_nodes, "node", false)?;
            distinct(&l, &e, "node")?;
            Some((e, l))
        }
        None => None,
    };
    let tri_codings = triangles(&mut take, n_nodes, &edges)?;
    let triangles = tri_codings.first().map(|(t, _)| t.clone());
    let tets = tetrahedra(&mut tet_blocks, n_nodes, &tri_codings, &edges)?;
    let primary = &tet_blocks[0].1;
    let n_tets = tets.len();

    let mesh = TetMesh::new(nodes, tets).map_err(|e| match e.tet() {
        Some(t) => primary.row_error(t, e.detail()),
        None => ParseError::new(file, primary.decl.line, e.to_string()),
    })?;
    if mesh.reoriented() > 0 {
        warnings.push(Warning {
            file: file.to_string(),
            line: Some(primary.decl.line),
            message: format!(
                "{} of {} tetrahedra were negatively oriented and have been re-oriented",
                mesh.reoriented(),
                n_tets
            ),
        });
    }

    if let Some(l) = take.located(Target::Triangles(TriangleCoding::UpperLower)) {
        upper_lower(l, n_tets, &tri_codings, &mesh)?;
    }

    let tet_edges = match &edges {
        Some((list, l)) => Some(cell_edges(&mesh, list, l)?),
        None => None,
    };
    Ok(Some(Geometry {
        mesh,
        coord_type,
        edges: edges.map(|(e, _)| e),
        triangles,
        tet_edges,
    }))
}

/// The edge list a coding by edges refers to; an error if the file has none.
fn need_edges<'e, 'a>(
    edges: &'e Edges<'a>,
    user: &Located,
) -> Result<&'e (Vec<[u32; 2]>, Located<'a>), ParseError> {
    edges.as_ref().ok_or_else(|| {
        ParseError::new(
            user.file,
            user.decl.line,
            format!(
                "{} needs an Edges block ('Edges {{ int[2] FromTo }} = @…')",
                user.decl.target.describe()
            ),
        )
    })
}

/// Triangles, by nodes and/or by edges (which must agree).
fn triangles<'a>(
    take: &mut Take<'a, '_>,
    n_nodes: usize,
    edges: &Edges,
) -> Result<TriangleCodings<'a>, ParseError> {
    let mut tri_codings: TriangleCodings = Vec::new();
    if let Some(mut l) = take.located(Target::Triangles(TriangleCoding::Nodes)) {
        let t = l.indices::<3>(n_nodes, "node", false)?;
        distinct(&l, &t, "node")?;
        tri_codings.push((t, l));
    }
    if let Some(mut l) = take.located(Target::Triangles(TriangleCoding::Edges)) {
        let (edge_list, _) = need_edges(edges, &l)?;
        let by_edges = l.indices::<3>(edge_list.len(), "edge", false)?;
        distinct(&l, &by_edges, "edge")?;
        let mut t = Vec::with_capacity(by_edges.len());
        for (row, es) in by_edges.iter().enumerate() {
            t.push(
                triangle_from_edges(es.map(|e| edge_list[e as usize])).ok_or_else(|| {
                    l.row_error(
                        row,
                        format!("edges {} do not form a triangle", show_nodes(es)),
                    )
                })?,
            );
        }
        tri_codings.push((t, l));
    }
    check_codings(
        &tri_codings
            .iter()
            .map(|(t, l)| (t.as_slice(), l))
            .collect::<Vec<_>>(),
        "triangle",
    )?;
    Ok(tri_codings)
}

/// Tetrahedra, by every coding given (which must agree); the first one (Nodes, Triangles,
/// Edges) is primary and its cells are returned.
fn tetrahedra(
    tet_blocks: &mut [(TetCoding, Located)],
    n_nodes: usize,
    tri_codings: &TriangleCodings,
    edges: &Edges,
) -> Result<Vec<[u32; 4]>, ParseError> {
    let mut tet_codings: Vec<Vec<[u32; 4]>> = Vec::new();
    for (coding, l) in tet_blocks.iter_mut() {
        let tets = match coding {
            TetCoding::Nodes => {
                let t = l.indices::<4>(n_nodes, "node", false)?;
                distinct(l, &t, "node")?;
                t
            }
            TetCoding::Triangles => tets_by_triangles(l, tri_codings)?,
            TetCoding::Edges => tets_by_edges(l, edges)?,
        };
        tet_codings.push(tets);
    }
    check_codings(
        &tet_codings
            .iter()
            .zip(tet_blocks.iter())
            .map(|(t, (_, l))| (t.as_slice(), l))
            .collect::<Vec<_>>(),
        "tetrahedron",
    )?;
    // Keep only the primary coding's cells; the others were only needed for the check.
    tet_codings.truncate(1);
    Ok(tet_codings.swap_remove(0))
}

/// `Tetrahedra { int[4] Triangles }`: four triangles, face i opposite node i.
fn tets_by_triangles(
    l: &mut Located,
    tri_codings: &TriangleCodings,
) -> Result<Vec<[u32; 4]>, ParseError> {
    let Some((tris, _)) = tri_codings.first() else {
        return Err(ParseError::new(
            l.file,
            l.decl.line,
            "Tetrahedra by Triangles need the triangles' nodes: expected 'Triangles { int[3] Nodes }' or '{ int[3] Edges }'",
        ));
    };
    let by_tris = l.indices::<4>(tris.len(), "triangle", false)?;
    distinct(l, &by_tris, "triangle")?;
    let mut t = Vec::with_capacity(by_tris.len());
    for (row, fs) in by_tris.iter().enumerate() {
        t.push(
            tet_from_triangles(fs.map(|f| tris[f as usize])).ok_or_else(|| {
                l.row_error(
                    row,
                    format!(
                        "triangles {} do not form a tetrahedron with face i opposite node i",
                        show_nodes(fs)
                    ),
                )
            })?,
        );
    }
    Ok(t)
}

/// `Tetrahedra { int[6] Edges }`: six edges in the coding order.
fn tets_by_edges(l: &mut Located, edges: &Edges) -> Result<Vec<[u32; 4]>, ParseError> {
    let (edge_list, _) = need_edges(edges, l)?;
    let by_edges = l.indices::<6>(edge_list.len(), "edge", false)?;
    distinct(l, &by_edges, "edge")?;
    let mut t = Vec::with_capacity(by_edges.len());
    for (row, es) in by_edges.iter().enumerate() {
        t.push(tet_from_edges(es.map(|e| edge_list[e as usize])).ok_or_else(|| {
            l.row_error(row, format!(
                "edges {} do not form a tetrahedron in the coding order (n0n1, n0n2, n0n3, n1n2, n1n3, n2n3)",
                show_nodes(es)
            ))
        })?);
    }
    Ok(t)
}

/// `Triangles { int[2] UpperLower }`: the (up to) two tetrahedra of each triangle, 0 for none;
/// each must have the triangle as a face.
fn upper_lower(
    mut l: Located,
    n_tets: usize,
    tri_codings: &TriangleCodings,
    mesh: &TetMesh,
) -> Result<(), ParseError> {
    let ul = l.indices::<2>(n_tets, "tetrahedron", true)?;
    if let Some((tris, _)) = tri_codings.first() {
        for (row, pair) in ul.iter().enumerate() {
            for &t in pair.iter().filter(|&&t| t != NONE) {
                let cell = mesh.tets()[t as usize];
                if !tris
                    .get(row)
                    .is_some_and(|tri| tri.iter().all(|n| cell.contains(n)))
                {
                    return Err(l.row_error(
                        row,
                        format!(
                            "tetrahedron {} does not have this triangle as a face",
                            t + 1
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Several codings of the same elements must describe the same node sets.
fn check_codings<const N: usize>(
    codings: &[(&[[u32; N]], &Located)],
    noun: &str,
) -> Result<(), ParseError> {
    let Some(((first, first_loc), rest)) = codings.split_first() else {
        return Ok(());
    };
    for (other, l) in rest {
        for (row, (a, b)) in first.iter().zip(other.iter()).enumerate() {
            if sorted(*a) != sorted(*b) {
                return Err(l.row_error(
                    row,
                    format!(
                        "this {noun} coding gives nodes {} but {} gives {}",
                        show_nodes(b),
                        first_loc.decl.target.describe(),
                        show_nodes(a)
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Three edges (any order, any direction) → the triangle's three nodes.
fn triangle_from_edges(e: [[u32; 2]; 3]) -> Option<[u32; 3]> {
    let [a, b] = e[0];
    let c = if e[1].contains(&a) || e[1].contains(&b) {
        *e[1].iter().find(|n| **n != a && **n != b)?
    } else {
        return None;
    };
    let tri = [a, b, c];
    // Every edge must join two distinct nodes of the triangle, and all three pairs must occur.
    let pairs = e.map(sorted);
    let want = [sorted([a, b]), sorted([a, c]), sorted([b, c])];
    want.iter().all(|w| pairs.contains(w)).then_some(tri)
}

/// Four triangles, face i opposite node i → the cell's nodes.
fn tet_from_triangles(f: [[u32; 3]; 4]) -> Option<[u32; 4]> {
    let mut all: Vec<u32> = f.iter().flatten().copied().collect();
    all.sort_unstable();
    all.dedup();
    if all.len() != 4 {
        return None;
    }
    let mut tet = [0u32; 4];
    for i in 0..4 {
        let missing: Vec<u32> = all.iter().copied().filter(|n| !f[i].contains(n)).collect();
        if missing.len() != 1 {
            return None;
        }
        tet[i] = missing[0];
    }
    (sorted(tet) == [all[0], all[1], all[2], all[3]]).then_some(tet)
}

/// Six edges in the order (n0n1, n0n2, n0n3, n1n2, n1n3, n2n3) → the cell's nodes.
fn tet_from_edges(e: [[u32; 2]; 6]) -> Option<[u32; 4]> {
    let n0 = *e[0].iter().find(|n| e[1].contains(n) && e[2].contains(n))?;
    let other = |p: [u32; 2]| if p[0] == n0 { p[1] } else { p[0] };
    let tet = [n0, other(e[0]), other(e[1]), other(e[2])];
    EDGE_NODES
        .iter()
        .zip(e)
        .all(|(&[i, j], p)| sorted([tet[i], tet[j]]) == sorted(p))
        .then_some(tet)
}

/// Each cell's six edges as indices into the file's edge list (bit 31: directed j → i).
fn cell_edges(mesh: &TetMesh, list: &[[u32; 2]], l: &Located) -> Result<Vec<[u32; 6]>, ParseError> {
    let index = edge_index(list).map_err(|(e, first)| {
        let [a, b] = list[e];
        l.row_error(
            e,
            format!(
                "joins nodes {} and {} like edge {} does; every edge must appear once",
                a + 1,
                b + 1,
                first + 1
            ),
        )
    })?;
    Ok(edges_of_cells(mesh, list, &index))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_become_triangles_and_tets() {
        assert_eq!(
            triangle_from_edges([[0, 1], [2, 1], [0, 2]]),
            Some([0, 1, 2])
        );
        assert_eq!(triangle_from_edges([[0, 1], [1, 2], [2, 3]]), None);
        let tet = [4, 7, 1, 9];
        let edges = EDGE_NODES.map(|[i, j]| [tet[j], tet[i]]);
        assert_eq!(tet_from_edges(edges), Some(tet));
        let mut bad = edges;
        bad.swap(3, 4);
        assert_eq!(tet_from_edges(bad), None);
    }

    #[test]
    fn triangles_become_tets() {
        let tet = [4, 7, 1, 9];
        let faces = crate::mesh::FACE_NODES.map(|f| f.map(|k| tet[k]));
        assert_eq!(tet_from_triangles(faces), Some(tet));
        let mut bad = faces;
        bad.swap(0, 1);
        assert_eq!(tet_from_triangles(bad), Some([7, 4, 1, 9]));
        assert_eq!(
            tet_from_triangles([[0, 1, 2], [0, 1, 2], [0, 1, 3], [0, 2, 3]]),
            None
        );
    }
}
