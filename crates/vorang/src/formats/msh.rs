//! Gmsh meshes (`.msh`), format versions 2.2 and 4.1, ASCII and binary.
//!
//! Read: `$Nodes`, `$Elements` (Gmsh element types become VTK cell types; the 10-node
//! tetrahedron's last two nodes are swapped into VTK order), `$PhysicalNames` and, in 4.1,
//! `$Entities` for the physical groups, `$NodeData` and `$ElementData` (one array per section,
//! named by its first string tag). Other sections (`$Periodic`, `$ElementNodeData`, `$Parametrizations`, …) are read
//! past.
//!
//! Arrays, in file order: first the point arrays (`$NodeData`), then the cell arrays: the
//! physical group of each element as the integer cell array `gmsh:physical` (0 = none; in 4.1
//! the first physical tag of the element's entity), then every `$ElementData`. Element data that
//! Gmsh stores as doubles but that are all whole numbers in 0…255 (material ids, region
//! numbers) are read as integers, so they become `byte` fields usable by `CONST_CELL` and
//! `CategoryField`.
//!
//! Node and element tags may be sparse; data refer to them by tag. Binary files carry their own
//! byte order (the `1` after the format line).

use std::collections::HashMap;

use super::text::Cursor;
use super::{Array, ArrayValues, MeshDescription, cell_type};
use crate::error::ParseError;

pub fn sniff(head: &[u8]) -> bool {
    let start = head
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    head[start..].starts_with(b"$MeshFormat")
}

/// VTK cell type and node count of a Gmsh element type (255 = a type VoRANG does not name).
fn element_type(t: i64) -> Option<(u8, usize)> {
    Some(match t {
        1 => (cell_type::LINE, 2),
        2 => (cell_type::TRIANGLE, 3),
        3 => (cell_type::QUAD, 4),
        4 => (cell_type::TETRA, 4),
        5 => (cell_type::HEXAHEDRON, 8),
        6 => (cell_type::WEDGE, 6),
        7 => (cell_type::PYRAMID, 5),
        8 => (21, 3),
        9 => (22, 6),
        10 => (28, 9),
        11 => (cell_type::QUADRATIC_TETRA, 10),
        12 => (29, 27),
        13 => (32, 18),
        14 => (255, 14),
        15 => (cell_type::VERTEX, 1),
        16 => (23, 8),
        17 => (25, 20),
        18 => (26, 15),
        19 => (27, 13),
        20 => (255, 9),
        21 => (69, 10),
        22 => (255, 12),
        23 => (255, 15),
        24 => (255, 15),
        25 => (255, 21),
        26 => (68, 4),
        27 => (68, 5),
        28 => (68, 6),
        29 => (71, 20),
        30 => (71, 35),
        31 => (71, 56),
        92 => (72, 64),
        93 => (72, 125),
        _ => return None,
    })
}

struct Msh<'a> {
    c: Cursor<'a>,
    binary: bool,
    swap: bool,
    size_t: usize,
}

impl<'a> Msh<'a> {
    fn bytes(&mut self, n: usize, what: &str) -> Result<&'a [u8], ParseError> {
        self.c.raw(n, what)
    }

    fn word(&mut self, size: usize, what: &str) -> Result<u64, ParseError> {
        let b = self.bytes(size, what)?;
        let mut w = [0u8; 8];
        if self.swap {
            for (i, x) in b.iter().rev().enumerate() {
                w[i] = *x;
            }
        } else {
            w[..size].copy_from_slice(b);
        }
        Ok(u64::from_le_bytes(w))
    }

    /// A signed 32-bit int (binary) or an integer token (ASCII).
    fn int(&mut self, what: &str) -> Result<i64, ParseError> {
        if self.binary {
            Ok(i64::from(self.word(4, what)? as u32 as i32))
        } else {
            self.c.int(what)
        }
    }

    /// A `size_t` (binary 4.1) or an integer token.
    fn size(&mut self, what: &str) -> Result<u64, ParseError> {
        if self.binary {
            self.word(self.size_t, what)
        } else {
            let v = self.c.int(what)?;
            u64::try_from(v).map_err(|_| self.c.err(format!("expected {what} ≥ 0, found {v}")))
        }
    }

    fn double(&mut self, what: &str) -> Result<f64, ParseError> {
        if self.binary {
            Ok(f64::from_bits(self.word(8, what)?))
        } else {
            self.c.float(what)
        }
    }

    /// A count that the rest of the file can hold at `min_bytes` per item.
    fn bounded(
        &self,
        n: u64,
        min_bytes: usize,
        what: &str,
        line: usize,
    ) -> Result<usize, ParseError> {
        let left = (self.c.bytes.len() - self.c.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left + 1 {
            return Err(self.c.err_at(
                line,
                format!("{what} is {n}, more than the {left} bytes left in the file can hold"),
            ));
        }
        Ok(n as usize)
    }

    /// Moves past `$End<section>`.
    fn end(&mut self, section: &str) -> Result<(), ParseError> {
        let want = format!("$End{section}");
        loop {
            let Some((t, _)) = self.c.token() else {
                return Err(self
                    .c
                    .err(format!("unexpected end of file: expected {want}")));
            };
            if t == want {
                return Ok(());
            }
            if t.starts_with('$') && !self.binary {
                return Err(self.c.err(format!("expected {want}, found '{t}'")));
            }
        }
    }
}

struct Data {
    name: String,
    components: usize,
    /// Tag → values.
    entries: Vec<(u64, Vec<f64>)>,
    line: usize,
    on_nodes: bool,
}

pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let mut m = Msh {
        c: Cursor::new(bytes, name),
        binary: false,
        swap: false,
        size_t: 8,
    };
    let (t, _) = m.c.expect_token("$MeshFormat")?;
    if t != "$MeshFormat" {
        return Err(m.c.err_at(1, format!("expected $MeshFormat, found '{t}'")));
    }
    let (ver, vline) = m.c.expect_token("the format version")?;
    let version = match ver {
        "2.2" | "2.1" | "2" | "2.0" => 2,
        "4.1" => 4,
        v => {
            return Err(m.c.err_at(
                vline,
                format!("Gmsh format version {v}: VoRANG reads versions 2.2 and 4.1"),
            ));
        }
    };
    let ft = m.c.int("the file type (0 ASCII, 1 binary)")?;
    let ds = m.c.int("the data size")?;
    if !(ft == 0 || ft == 1) || !(ds == 4 || ds == 8) {
        return Err(m.c.err_at(
            vline,
            format!("expected file type 0 or 1 and data size 4 or 8, found {ft} {ds}"),
        ));
    }
    m.size_t = ds as usize;
    if ft == 1 {
        m.binary = true;
        m.c.next_line();
        let one = m.bytes(4, "the byte-order check")?;
        if one == 1u32.to_le_bytes() {
            m.swap = false;
        } else if one == 1u32.to_be_bytes() {
            m.swap = true;
        } else {
            return Err(m.c.err(format!(
                "the binary byte-order check is not the integer 1 (bytes {one:?})"
            )));
        }
    }
    m.end("MeshFormat")?;

    let mut desc = MeshDescription {
        source: name.to_string(),
        format: format!("Gmsh {ver} {}", if m.binary { "binary" } else { "ASCII" }),
        ..MeshDescription::default()
    };
    let mut node_index: HashMap<u64, usize> = HashMap::new();
    let mut element_tags: Vec<u64> = Vec::new();
    let mut physical: Vec<i64> = Vec::new();
    let mut has_physical = false;
    // 4.1: (dim, entity tag) → first physical tag.
    let mut entity_physical: HashMap<(i64, i64), i64> = HashMap::new();
    let mut data: Vec<Data> = Vec::new();
    let mut raw_elements: Vec<(u8, Vec<u64>, usize)> = Vec::new(); // type, node tags, line
    while let Some((sec, line)) = m.c.token() {
        match sec {
            "$PhysicalNames" => {
                has_physical = true;
                m.end("PhysicalNames")?;
            }
            "$Entities" if version == 4 => {
                if m.binary {
                    m.c.next_line();
                }
                let counts = [0; 4].map(|_| m.size("an entity count"));
                let counts: Vec<u64> = counts.into_iter().collect::<Result<_, _>>()?;
                for (dim, &n) in counts.iter().enumerate() {
                    let n = m.bounded(n, 8, "the entity count", line)?;
                    for _ in 0..n {
                        let tag = m.int("an entity tag")?;
                        let coords = if dim == 0 { 3 } else { 6 };
                        for _ in 0..coords {
                            m.double("an entity bounding box")?;
                        }
                        let np = m.size("the number of physical tags")?;
                        let np = m.bounded(np, 1, "the number of physical tags", line)?;
                        for k in 0..np {
                            let p = m.int("a physical tag")?;
                            if k == 0 {
                                entity_physical.insert((dim as i64, tag), p);
                            }
                        }
                        if dim > 0 {
                            let nb = m.size("the number of bounding entities")?;
                            let nb = m.bounded(nb, 1, "the number of bounding entities", line)?;
                            for _ in 0..nb {
                                m.int("a bounding entity")?;
                            }
                        }
                    }
                }
                m.end("Entities")?;
            }
            "$Nodes" => {
                desc.points_line = line;
                if version == 2 {
                    let n = m.c.count("the number of nodes", 0)?;
                    let n = m.bounded(
                        n as u64,
                        if m.binary { 28 } else { 8 },
                        "the number of nodes",
                        line,
                    )?;
                    if m.binary {
                        m.c.next_line();
                    }
                    desc.nodes.reserve(n);
                    for _ in 0..n {
                        let tag = m.int("a node tag")?;
                        let p = [m.double("x")?, m.double("y")?, m.double("z")?];
                        if node_index.insert(tag as u64, desc.nodes.len()).is_some() {
                            return Err(m.c.err(format!("node tag {tag} appears twice")));
                        }
                        desc.nodes.push(p);
                    }
                } else {
                    if m.binary {
                        m.c.next_line();
                    }
                    let blocks = m.size("the number of entity blocks")?;
                    let total = m.size("the number of nodes")?;
                    m.size("the smallest node tag")?;
                    m.size("the largest node tag")?;
                    let blocks = m.bounded(blocks, 4, "the number of node blocks", line)?;
                    let total = m.bounded(total, 8, "the number of nodes", line)?;
                    desc.nodes.reserve(total);
                    for _ in 0..blocks {
                        let bline = m.c.line;
                        let _dim = m.int("the entity dimension")?;
                        let _tag = m.int("the entity tag")?;
                        let parametric = m.int("the parametric flag")?;
                        let n = m.size("the number of nodes in the block")?;
                        let n = m.bounded(n, 8, "the number of nodes in the block", bline)?;
                        if parametric != 0 {
                            return Err(m.c.err_at(bline, "parametric node coordinates are not supported; save the mesh without them"));
                        }
                        let mut tags = Vec::with_capacity(n);
                        for _ in 0..n {
                            tags.push(m.size("a node tag")?);
                        }
                        for tag in tags {
                            let p = [m.double("x")?, m.double("y")?, m.double("z")?];
                            if node_index.insert(tag, desc.nodes.len()).is_some() {
                                return Err(m.c.err(format!("node tag {tag} appears twice")));
                            }
                            desc.nodes.push(p);
                        }
                    }
                }
                m.end("Nodes")?;
            }
            "$Elements" => {
                desc.cells_line = line;
                if version == 2 {
                    let n = m.c.count("the number of elements", 0)?;
                    let n = m.bounded(n as u64, 8, "the number of elements", line)?;
                    if m.binary {
                        m.c.next_line();
                        let mut done = 0;
                        while done < n {
                            let ty = m.int("the element type")?;
                            let count = m.int("the number of elements that follow")?;
                            let ntags = m.int("the number of tags")?;
                            let (vtk, nn) = element_type(ty).ok_or_else(|| {
                                m.c.err(format!("unknown Gmsh element type {ty}"))
                            })?;
                            if count <= 0 || ntags < 0 || done + count as usize > n {
                                return Err(m.c.err(format!("element block of {count} elements with {ntags} tags does not fit the {n} elements declared")));
                            }
                            let count =
                                m.bounded(count as u64, 4 * (1 + nn), "the element block", line)?;
                            for _ in 0..count {
                                let id = m.int("an element tag")?;
                                let mut phys = 0;
                                for k in 0..ntags {
                                    let t = m.int("an element tag value")?;
                                    if k == 0 {
                                        phys = t;
                                    }
                                }
                                let mut nodes = Vec::with_capacity(nn);
                                for _ in 0..nn {
                                    nodes.push(m.int("an element node")? as u64);
                                }
                                element_tags.push(id as u64);
                                physical.push(phys);
                                raw_elements.push((vtk, nodes, m.c.line));
                            }
                            done += count;
                        }
                    } else {
                        for _ in 0..n {
                            let (first, eline) = m.c.expect_token("an element")?;
                            let rest = m.c.rest_of_line();
                            let nums: Vec<i64> = std::iter::once(first)
                                .chain(rest.split_whitespace())
                                .map(|t| {
                                    super::text::parse_int(t).ok_or_else(|| {
                                        m.c.err_at(
                                            eline,
                                            format!(
                                                "expected integers in an element line, found '{t}'"
                                            ),
                                        )
                                    })
                                })
                                .collect::<Result<_, _>>()?;
                            if nums.len() < 3 {
                                return Err(m.c.err_at(
                                    eline,
                                    "an element line needs a tag, a type and a number of tags",
                                ));
                            }
                            let ntags = usize::try_from(nums[2].max(0)).unwrap_or(usize::MAX);
                            if nums.len() - 3 < ntags {
                                return Err(m.c.err_at(
                                    eline,
                                    "the element line is shorter than its number of tags",
                                ));
                            }
                            let nodes: Vec<u64> =
                                nums[3 + ntags..].iter().map(|&x| x.max(0) as u64).collect();
                            let vtk = match element_type(nums[1]) {
                                Some((vtk, nn)) if nn == nodes.len() => vtk,
                                Some((_, nn)) => {
                                    return Err(m.c.err_at(
                                        eline,
                                        format!(
                                            "element {}: type {} has {nn} nodes, the line gives {}",
                                            nums[0],
                                            nums[1],
                                            nodes.len()
                                        ),
                                    ));
                                }
                                None => 255,
                            };
                            element_tags.push(nums[0] as u64);
                            physical.push(if ntags > 0 { nums[3] } else { 0 });
                            raw_elements.push((vtk, nodes, eline));
                        }
                    }
                    if physical.iter().any(|&p| p != 0) {
                        has_physical = true;
                    }
                } else {
                    if m.binary {
                        m.c.next_line();
                    }
                    let blocks = m.size("the number of entity blocks")?;
                    let total = m.size("the number of elements")?;
                    m.size("the smallest element tag")?;
                    m.size("the largest element tag")?;
                    let blocks = m.bounded(blocks, 4, "the number of element blocks", line)?;
                    m.bounded(total, 8, "the number of elements", line)?;
                    for _ in 0..blocks {
                        let bline = m.c.line;
                        let dim = m.int("the entity dimension")?;
                        let tag = m.int("the entity tag")?;
                        let ty = m.int("the element type")?;
                        let n = m.size("the number of elements in the block")?;
                        let (vtk, nn) = element_type(ty).ok_or_else(|| {
                            m.c.err_at(bline, format!("unknown Gmsh element type {ty}"))
                        })?;
                        let n = m.bounded(
                            n,
                            2 * (1 + nn),
                            "the number of elements in the block",
                            bline,
                        )?;
                        let phys = entity_physical.get(&(dim, tag)).copied().unwrap_or(0);
                        for _ in 0..n {
                            let eline = m.c.line;
                            let id = m.size("an element tag")?;
                            let mut nodes = Vec::with_capacity(nn);
                            for _ in 0..nn {
                                nodes.push(m.size("an element node")?);
                            }
                            element_tags.push(id);
                            physical.push(phys);
                            raw_elements.push((vtk, nodes, eline));
                        }
                    }
                    if !entity_physical.is_empty() {
                        has_physical = true;
                    }
                }
                m.end("Elements")?;
            }
            "$NodeData" | "$ElementData" => {
                let on_nodes = sec == "$NodeData";
                let ns = m.c.count("the number of string tags", 0)?;
                let mut dname = String::new();
                for k in 0..ns {
                    m.c.skip_space();
                    let s = m.c.rest_of_line().trim().trim_matches('"').to_string();
                    if k == 0 {
                        dname = s;
                    }
                }
                let nr = m.c.count("the number of real tags", 0)?;
                for _ in 0..nr {
                    m.c.float("a real tag")?;
                }
                let ni = m.c.count("the number of integer tags", 0)?;
                let mut ints = Vec::new();
                for _ in 0..ni {
                    ints.push(m.c.int("an integer tag")?);
                }
                let comps = ints.get(1).copied().unwrap_or(1);
                let count = ints.get(2).copied().unwrap_or(0);
                if !(1..=9).contains(&comps) || count < 0 {
                    return Err(m.c.err_at(
                        line,
                        format!(
                            "{sec}: {comps} components and {count} entries: expected 1…9 components"
                        ),
                    ));
                }
                let comps = comps as usize;
                let per = if m.binary {
                    4 + 8 * comps
                } else {
                    2 * (1 + comps)
                };
                let count = m.bounded(count as u64, per, "the number of entries", line)?;
                if m.binary {
                    m.c.next_line();
                }
                let mut entries = Vec::with_capacity(count);
                for _ in 0..count {
                    let tag = m.int("an entity tag")?;
                    let mut v = Vec::with_capacity(comps);
                    for _ in 0..comps {
                        v.push(m.double("a value")?);
                    }
                    entries.push((tag.max(0) as u64, v));
                }
                m.end(&sec[1..])?;
                if dname.is_empty() {
                    dname = format!("data{}", data.len());
                }
                data.push(Data {
                    name: dname,
                    components: comps,
                    entries,
                    line,
                    on_nodes,
                });
            }
            s if s.starts_with('$') && !s.starts_with("$End") => {
                // A section VoRANG does not use: skip to its end marker.
                let want = format!("$End{}", &s[1..]);
                if m.binary {
                    let Some(k) = find(&bytes[m.c.pos..], want.as_bytes()) else {
                        return Err(m.c.err_at(line, format!("{s} is not closed by {want}")));
                    };
                    m.c.raw(k + want.len(), s)?;
                } else {
                    m.end(&s[1..])?;
                }
            }
            other => {
                return Err(m.c.err_at(
                    line,
                    format!("expected a section such as $Nodes or $Elements, found '{other}'"),
                ));
            }
        }
    }
    if desc.nodes.is_empty() {
        return Err(ParseError::new(
            name,
            m.c.line,
            "no $Nodes section (or no nodes) in this file",
        ));
    }
    // Elements: node tags → indices.
    desc.cells.offsets.push(0);
    for (i, (vtk, tags, eline)) in raw_elements.iter().enumerate() {
        let mut nodes = Vec::with_capacity(tags.len());
        for &t in tags {
            match node_index.get(&t) {
                Some(&k) => nodes.push(k as u64),
                None if cell_type::volume_nodes(*vtk).is_some() => {
                    return Err(ParseError::new(
                        name,
                        *eline,
                        format!(
                            "element {} refers to node tag {t}, which $Nodes does not define",
                            element_tags[i]
                        ),
                    ));
                }
                None => nodes.push(0),
            }
        }
        if *vtk == cell_type::QUADRATIC_TETRA {
            nodes.swap(8, 9);
        }
        desc.cells.push(*vtk, &nodes);
    }
    if has_physical {
        desc.cell_arrays.push(Array {
            name: "gmsh:physical".into(),
            components: 1,
            values: ArrayValues::Int(physical),
            line: desc.cells_line,
        });
    }
    let element_index: HashMap<u64, usize> = element_tags
        .iter()
        .enumerate()
        .map(|(i, &t)| (t, i))
        .collect();
    let mut points = Vec::new();
    let mut cells = Vec::new();
    for d in data {
        let (index, n) = if d.on_nodes {
            (&node_index, desc.nodes.len())
        } else {
            (&element_index, desc.cells.len())
        };
        let mut values = vec![0.0; n * d.components];
        for (tag, v) in &d.entries {
            let Some(&k) = index.get(tag) else {
                return Err(ParseError::new(
                    name,
                    d.line,
                    format!(
                        "{} \"{}\" gives a value for {} tag {tag}, which the mesh does not have",
                        if d.on_nodes {
                            "$NodeData"
                        } else {
                            "$ElementData"
                        },
                        d.name,
                        if d.on_nodes { "node" } else { "element" }
                    ),
                ));
            };
            values[k * d.components..(k + 1) * d.components].copy_from_slice(v);
        }
        let integral = !d.on_nodes
            && d.components == 1
            && values
                .iter()
                .all(|&v| v.fract() == 0.0 && (0.0..=255.0).contains(&v));
        let values = if integral {
            ArrayValues::Int(values.iter().map(|&v| v as i64).collect())
        } else {
            ArrayValues::F64(values)
        };
        let a = Array {
            name: d.name,
            components: d.components,
            values,
            line: d.line,
        };
        if d.on_nodes {
            points.push(a);
        } else {
            cells.push(a);
        }
    }
    desc.point_arrays = points;
    desc.cell_arrays.extend(cells);
    Ok(desc)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}
