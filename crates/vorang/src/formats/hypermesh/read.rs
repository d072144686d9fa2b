//! Reading a HyperMesh file: header, blocks, then resolving the geometry (every coding of
//! triangles and tetrahedra becomes node indices), the mesh, the raw data and the fields.
//!
//! Indices in files are 1-based (SPEC §7 **Decision**); in memory they are 0-based `u32`.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::Path;

use super::ascii::{self, BlockInfo, RowLines, element_noun, marker_line};
use super::binary;
use super::header::{
    BlockDecl, Encoding, Header, HeaderParser, Target, TetCoding, TriangleCoding, is_marker_char,
    parse_title,
};
use super::input::Input;
use crate::data::{ElementKind, RawData, Values};
use crate::error::{Error, ParseError, Warning};
use crate::field::{Field, Interpolator, Origin};
use crate::mesh::{EDGE_NODES, TetMesh};
use crate::volume::DataSet;

pub use crate::mesh::edges::{NONE, edge_index, edges_of_cells};

pub use crate::volume::Geometry;

/// Everything a HyperMesh file holds.
#[derive(Debug, Clone, PartialEq)]
pub struct HyperMeshFile {
    pub name: String,
    pub encoding: Encoding,
    pub version: String,
    /// `None` for a data-only file (no tetrahedra).
    pub geometry: Option<Geometry>,
    pub data: DataSet,
    pub warnings: Vec<Warning>,
}

/// Reads a file from disk.
pub fn read_file(path: &Path) -> Result<HyperMeshFile, Error> {
    let f = File::open(path).map_err(|e| Error::io(path, e))?;
    let meta = f.metadata().map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::other("is a directory, expected a HyperMesh file"),
        ));
    }
    let reader = BufReader::with_capacity(1 << 16, f);
    Ok(read(reader, &path.display().to_string(), Some(meta.len()))?)
}

/// Reads a file held in memory (`name` labels messages).
pub fn read_bytes(bytes: &[u8], name: &str) -> Result<HyperMeshFile, ParseError> {
    read(bytes, name, Some(bytes.len() as u64))
}

/// Reads from any buffered source; `size` (total bytes, if known) bounds allocations.
pub fn read<R: BufRead>(
    reader: R,
    name: &str,
    size: Option<u64>,
) -> Result<HyperMeshFile, ParseError> {
    let mut input = Input::new(reader, size);
    let (header, mut blocks, field_blocks) = read_blocks(&mut input, name)?;
    let mut warnings = Vec::new();
    let geometry = resolve_geometry(name, &header, &mut blocks, &mut warnings)?;
    let data = resolve_data(name, &header, &mut blocks, &field_blocks)?;
    Ok(HyperMeshFile {
        name: name.to_string(),
        encoding: header.encoding,
        version: header.version,
        geometry,
        data,
        warnings,
    })
}

/// Reads a HyperMesh header held as text whose blocks are stored elsewhere (the layout that
/// VoRANG writes into its `.vtu` files, [`crate::formats::layout`]): `block(decl, count)` gives
/// the values of each declared block (`count` elements of `decl.ty`), or says why it cannot.
/// The geometry, raw data and fields are then resolved exactly as for a file, so a volume
/// written this way reads back identical. Every message points at `line` (where the text is
/// stored in its file) and says which line of the text it is about.
pub fn read_with_blocks(
    name: &str,
    text: &[u8],
    line: usize,
    mut block: impl FnMut(&BlockDecl, usize) -> Result<Values, String>,
) -> Result<HyperMeshFile, ParseError> {
    let at = |e: ParseError| {
        ParseError::new(
            name,
            line,
            format!("VoRANG layout, line {}: {}", e.line, e.message),
        )
    };
    let mut lines = text.split(|&b| b == b'\n');
    let (encoding, version) = parse_title(name, lines.next().unwrap_or_default()).map_err(at)?;
    let mut parser = HeaderParser::new(name);
    for (i, l) in lines.enumerate() {
        parser.push_line(i + 2, l).map_err(at)?;
    }
    let header = parser.finish(encoding, version).map_err(at)?;
    let field_blocks = resolve_field_markers(name, &header).map_err(at)?;
    let mut blocks = Vec::with_capacity(header.blocks.len());
    for d in &header.blocks {
        let count = block_count(name, &header, d).map_err(at)?;
        let values = block(d, count).map_err(|m| {
            ParseError::new(
                name,
                line,
                format!(
                    "VoRANG layout, block @{} ({}): {m}",
                    d.marker,
                    d.target.describe()
                ),
            )
        })?;
        if values.len() != count.saturating_mul(d.ty.numbers()) {
            return Err(ParseError::new(
                name,
                line,
                format!(
                    "VoRANG layout, block @{} ({}): {} numbers, but {count} × {} need {}",
                    d.marker,
                    d.target.describe(),
                    values.len(),
                    d.ty,
                    count.saturating_mul(d.ty.numbers())
                ),
            ));
        }
        blocks.push(Some(Block {
            values,
            rows: None,
            marker_line: line,
        }));
    }
    let mut warnings = Vec::new();
    let geometry = resolve_geometry(name, &header, &mut blocks, &mut warnings)?;
    let data = resolve_data(name, &header, &mut blocks, &field_blocks)?;
    Ok(HyperMeshFile {
        name: name.to_string(),
        encoding: header.encoding,
        version: header.version,
        geometry,
        data,
        warnings,
    })
}

/// The values of one block and where its rows are.
struct Block {
    values: Values,
    /// Row lines for ASCII blocks; `None` for BINARY ones.
    rows: Option<RowLines>,
    marker_line: usize,
}

/// The header, the blocks (parallel to its declarations) and the resolved `Field` markers.
type Blocks = (Header, Vec<Option<Block>>, Vec<(Interpolator, Vec<usize>)>);

fn read_blocks<R: BufRead>(input: &mut Input<R>, file: &str) -> Result<Blocks, ParseError> {
    let io_err = |line: usize, e: std::io::Error| {
        ParseError::new(file, line.max(1), format!("read error: {e}"))
    };
    let title = match input.next_line() {
        Ok(Some((_, l))) => l.to_vec(),
        Ok(None) => {
            return Err(ParseError::new(
                file,
                1,
                "empty file: expected the title line '# HyperMesh 3D ASCII 0.7'",
            ));
        }
        Err(e) => return Err(io_err(1, e)),
    };
    let (encoding, version) = parse_title(file, &title)?;
    let mut parser = HeaderParser::new(file);
    let mut pending = None;
    loop {
        match input.next_line() {
            Ok(Some((n, line))) => {
                if let Some(m) = marker_line(line) {
                    pending = Some((m.to_vec(), n));
                    break;
                }
                parser.push_line(n, line)?;
            }
            Ok(None) => break,
            Err(e) => return Err(io_err(input.line + 1, e)),
        }
    }
    let header = parser.finish(encoding, version)?;
    let field_blocks = resolve_field_markers(file, &header)?;
    let counts: Vec<usize> = header
        .blocks
        .iter()
        .map(|d| block_count(file, &header, d))
        .collect::<Result<_, _>>()?;
    let by_marker: HashMap<&str, usize> = header
        .blocks
        .iter()
        .enumerate()
        .map(|(i, b)| (b.marker.as_str(), i))
        .collect();
    let mut blocks: Vec<Option<Block>> = (0..header.blocks.len()).map(|_| None).collect();

    while let Some((text, line)) = pending.take() {
        let marker = parse_marker_line(file, &text, line)?;
        let Some(&i) = by_marker.get(marker.as_str()) else {
            let mut known: Vec<String> = header
                .blocks
                .iter()
                .map(|b| format!("@{}", b.marker))
                .collect();
            known.sort();
            return Err(ParseError::new(
                file,
                line,
                format!(
                    "block @{marker} is not declared in the header (declared: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        };
        if let Some(prev) = &blocks[i] {
            return Err(ParseError::new(
                file,
                line,
                format!(
                    "block @{marker} appears twice (first on line {})",
                    prev.marker_line
                ),
            ));
        }
        let decl = &header.blocks[i];
        let what = decl.target.describe();
        let kind = decl.target.element_kind();
        let info = BlockInfo {
            file,
            marker: &decl.marker,
            marker_line: line,
            what: &what,
            count_keyword: kind.count_keyword(),
        };
        let block = match encoding {
            Encoding::Ascii => {
                let b = ascii::read_block(input, &info, decl.ty, counts[i])?;
                pending = b.next_marker;
                Block {
                    values: b.values,
                    rows: Some(b.rows),
                    marker_line: line,
                }
            }
            Encoding::Binary => {
                let values = binary::read_block(input, &info, decl.ty, counts[i])?;
                pending = next_binary_marker(input, file, &decl.marker)?;
                Block {
                    values,
                    rows: None,
                    marker_line: line,
                }
            }
        };
        blocks[i] = Some(block);
    }
    for (d, b) in header.blocks.iter().zip(&blocks) {
        if b.is_none() {
            return Err(ParseError::new(
                file,
                d.line,
                format!(
                    "block @{} is declared here but never appears in the file",
                    d.marker
                ),
            ));
        }
    }
    Ok((header, blocks, field_blocks))
}

/// For every `Field` line: its interpolator and the declaration index of each marker. Checked
/// before any block is read, so a wrong name fails at once.
fn resolve_field_markers(
    file: &str,
    header: &Header,
) -> Result<Vec<(Interpolator, Vec<usize>)>, ParseError> {
    header
        .fields
        .iter()
        .map(|f| {
            let err = |msg: String| ParseError::new(file, f.line, msg);
            let Some(interp) = Interpolator::from_name(&f.interpolator) else {
                return Err(err(format!(
                    "unknown interpolator '{}': expected one of {}",
                    f.interpolator,
                    Interpolator::names()
                )));
            };
            let info = interp.info();
            let mut decls = Vec::with_capacity(f.markers.len());
            for (k, m) in f.markers.iter().enumerate() {
                let want = info.required.iter().chain(info.optional).nth(k).map_or("raw data", |w| w.data_keyword());
                match header.blocks.iter().position(|b| &b.marker == m) {
                    None => return Err(err(format!("marker @{m} is not declared in the header ({} needs {want})", info.name))),
                    Some(i) if !matches!(header.blocks[i].target, Target::Data(_)) => {
                        return Err(err(format!(
                            "{} needs {want} for marker {}, but @{m} is a {} block (geometry, not raw data)",
                            info.name,
                            k + 1,
                            header.blocks[i].target.describe()
                        )));
                    }
                    Some(i) => decls.push(i),
                }
            }
            Ok((interp, decls))
        })
        .collect()
}

/// The number of rows a declared block must have.
fn block_count(file: &str, header: &Header, d: &BlockDecl) -> Result<usize, ParseError> {
    let kind = d.target.element_kind();
    match header.count(kind) {
        Some(c) => Ok(c.value),
        // nExtra defaults to 1 (thesis B.2).
        None if kind == ElementKind::Extra => Ok(1),
        None => Err(ParseError::new(
            file,
            d.line,
            format!(
                "{} needs the count '{} = …' in the header",
                d.target.describe(),
                kind.count_keyword()
            ),
        )),
    }
}

/// `@name` followed by nothing but whitespace or a comment.
fn parse_marker_line(file: &str, text: &[u8], line: usize) -> Result<String, ParseError> {
    let body = &text[1..];
    let len = body.iter().take_while(|&&b| is_marker_char(b)).count();
    let rest = &body[len..];
    let rest_ok = rest
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .is_none_or(|i| rest[i] == b'#');
    if len == 0 || !rest_ok {
        return Err(ParseError::new(
            file,
            line,
            format!(
                "expected a marker line such as '@1', found '{}'",
                String::from_utf8_lossy(&text[..text.len().min(40)])
            ),
        ));
    }
    Ok(String::from_utf8_lossy(&body[..len]).into_owned())
}

/// After a BINARY block: skip blank and comment lines, return the next marker line, if any.
fn next_binary_marker<R: BufRead>(
    input: &mut Input<R>,
    file: &str,
    after: &str,
) -> Result<Option<(Vec<u8>, usize)>, ParseError> {
    loop {
        let next = input.line + 1;
        let line = input
            .next_line()
            .map_err(|e| ParseError::new(file, next, format!("read error: {e}")))?;
        let Some((n, line)) = line else {
            return Ok(None);
        };
        if let Some(m) = marker_line(line) {
            return Ok(Some((m.to_vec(), n)));
        }
        let blank = line
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .is_none_or(|i| line[i] == b'#');
        if !blank {
            return Err(ParseError::new(
                file,
                n,
                format!(
                    "expected the next '@marker' line after binary block @{after}, found other bytes (does the block's count match its data?)"
                ),
            ));
        }
    }
}

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

fn resolve_geometry(
    file: &str,
    header: &Header,
    blocks: &mut [Option<Block>],
    warnings: &mut Vec<Warning>,
) -> Result<Option<Geometry>, ParseError> {
    let mut loc = |t: Target| -> Option<Located> {
        let i = header.blocks.iter().position(|b| b.target == t)?;
        let b = blocks[i].as_mut()?;
        Some(Located {
            file,
            decl: &header.blocks[i],
            values: std::mem::replace(&mut b.values, Values::U8(Vec::new())),
            rows: b.rows.clone(),
            marker_line: b.marker_line,
        })
    };
    let mut tet_blocks: Vec<(TetCoding, Located)> =
        [TetCoding::Nodes, TetCoding::Triangles, TetCoding::Edges]
            .into_iter()
            .filter_map(|c| Some((c, loc(Target::Tetrahedra(c))?)))
            .collect();
    let Some(primary_line) = tet_blocks.first().map(|(_, l)| l.decl.line) else {
        return Ok(None);
    };
    let Some(mut node_loc) = loc(Target::Nodes) else {
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

    let edges = match loc(Target::Edges) {
        Some(mut l) => {
            let e = l.indices::<2>(n_nodes, "node", false)?;
            distinct(&l, &e, "node")?;
            Some((e, l))
        }
        None => None,
    };
    let need_edges = |user: &Located| -> Result<&(Vec<[u32; 2]>, Located), ParseError> {
        edges.as_ref().ok_or_else(|| {
            ParseError::new(
                file,
                user.decl.line,
                format!(
                    "{} needs an Edges block ('Edges {{ int[2] FromTo }} = @…')",
                    user.decl.target.describe()
                ),
            )
        })
    };

    // Triangles, by nodes and/or by edges.
    let mut tri_codings: Vec<(Vec<[u32; 3]>, Located)> = Vec::new();
    if let Some(mut l) = loc(Target::Triangles(TriangleCoding::Nodes)) {
        let t = l.indices::<3>(n_nodes, "node", false)?;
        distinct(&l, &t, "node")?;
        tri_codings.push((t, l));
    }
    if let Some(mut l) = loc(Target::Triangles(TriangleCoding::Edges)) {
        let (edge_list, _) = need_edges(&l)?;
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
    let triangles = tri_codings.first().map(|(t, _)| t.clone());

    // Tetrahedra, by every coding given; the first one (Nodes, Triangles, Edges) is primary.
    let mut tet_codings: Vec<Vec<[u32; 4]>> = Vec::new();
    for (coding, l) in &mut tet_blocks {
        let l: &mut Located = l;
        let tets = match coding {
            TetCoding::Nodes => {
                let t = l.indices::<4>(n_nodes, "node", false)?;
                distinct(l, &t, "node")?;
                t
            }
            TetCoding::Triangles => {
                let Some((tris, _)) = tri_codings.first() else {
                    return Err(ParseError::new(
                        file,
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
                            l.row_error(row, format!(
                            "triangles {} do not form a tetrahedron with face i opposite node i",
                            show_nodes(fs)
                        ))
                        })?,
                    );
                }
                t
            }
            TetCoding::Edges => {
                let (edge_list, _) = need_edges(l)?;
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
                t
            }
        };
        tet_codings.push(tets);
    }
    check_codings(
        &tet_codings
            .iter()
            .zip(&tet_blocks)
            .map(|(t, (_, l))| (t.as_slice(), l))
            .collect::<Vec<_>>(),
        "tetrahedron",
    )?;
    // Keep only the primary coding's cells; the others were only needed for the check.
    tet_codings.truncate(1);
    let tets = tet_codings.swap_remove(0);
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

    if let Some(mut l) = loc(Target::Triangles(TriangleCoding::UpperLower)) {
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

fn resolve_data(
    file: &str,
    header: &Header,
    blocks: &mut [Option<Block>],
    field_blocks: &[(Interpolator, Vec<usize>)],
) -> Result<DataSet, ParseError> {
    let mut raw = Vec::new();
    let mut raw_of_decl = vec![usize::MAX; header.blocks.len()];
    for (i, (d, b)) in header.blocks.iter().zip(blocks.iter_mut()).enumerate() {
        if let Target::Data(kind) = d.target {
            let Some(b) = b.take() else { continue };
            raw_of_decl[i] = raw.len();
            raw.push(RawData {
                kind,
                ty: d.ty,
                denominator: d.denominator.clone(),
                values: b.values,
            });
        }
    }
    let mut fields = Vec::with_capacity(header.fields.len());
    for (f, (interp, decls)) in header.fields.iter().zip(field_blocks) {
        let origin = Origin {
            file: file.to_string(),
            line: f.line,
        };
        let field = Field::build(
            f.name.clone(),
            f.ty,
            f.denominator.clone(),
            *interp,
            decls.iter().map(|&d| raw_of_decl[d]).collect(),
            &raw,
            header.materials.as_ref(),
            origin,
            &|k| format!("@{}", f.markers[k]),
        )
        .map_err(|msg| ParseError::new(file, f.line, msg))?;
        fields.push(field);
    }
    Ok(DataSet {
        materials: header.materials.clone(),
        counts: header.counts.map(|c| c.map(|c| c.value)),
        count_lines: header.counts.map(|c| c.map(|c| c.line)),
        raw,
        fields,
    })
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
