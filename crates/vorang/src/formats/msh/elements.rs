//! `$Elements`: Gmsh element types become VTK cell types, node tags stay tags until every
//! section is read (`$Nodes` may follow `$Elements`), then [`Sections::connect_elements`] turns
//! them into node indices. Three layouts, one function each: 2.2 ASCII (one element per line, its
//! tags inline), 2.2 binary (blocks of one type with a common number of tags) and 4.1 (entity
//! blocks, ASCII or binary alike, the physical group from `$Entities`).

use rayon::prelude::*;

use super::input::{Msh, int_of};
use super::{RawElements, Sections};
use crate::error::ParseError;
use crate::formats::cell_type;
use crate::formats::lines;
use crate::formats::text::parse_int;

/// A node index not known (yet): a tag `$Nodes` does not define, or an index beyond 32 bits
/// (stored as `u32::MAX` either way, as [`crate::formats::Cells`] does).
const UNKNOWN: u32 = u32::MAX;

/// A row of exactly `out.len()` whole numbers ≥ 0 (as `Msh::size` reads them).
pub(super) fn uints(line: &[u8], out: &mut [u64]) -> bool {
    let mut t = lines::tokens(line);
    for v in out.iter_mut() {
        match t.uint() {
            Some(x) => *v = x,
            None => return false,
        }
    }
    t.at_end()
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
        12 => (cell_type::TRIQUADRATIC_HEXAHEDRON, 27),
        13 => (cell_type::BIQUADRATIC_QUADRATIC_WEDGE, 18),
        14 => (255, 14),
        15 => (cell_type::VERTEX, 1),
        16 => (23, 8),
        17 => (cell_type::QUADRATIC_HEXAHEDRON, 20),
        18 => (cell_type::QUADRATIC_WEDGE, 15),
        19 => (cell_type::QUADRATIC_PYRAMID, 13),
        20 => (255, 9),
        21 => (69, 10),
        22 => (255, 12),
        23 => (255, 15),
        24 => (255, 15),
        25 => (255, 21),
        26 => (68, 4),
        27 => (68, 5),
        28 => (68, 6),
        // Tetrahedra and hexahedra of order 3 and more: Gmsh numbers their nodes otherwise
        // than VTK's Lagrange cells, so they are not read as those (skipped with the others).
        29 => (255, 20),
        30 => (255, 35),
        31 => (255, 56),
        92 => (255, 64),
        93 => (255, 125),
        _ => return None,
    })
}

/// For VTK's quadratic hexahedra, wedges and pyramids: the Gmsh node at each VTK node. Gmsh
/// numbers the edges of these elements by their first corner (the 20-node hexahedron:
/// 0-1, 0-3, 0-4, 1-2, …), VTK around the bottom, the top, then upwards; their faces in
/// another order too (Gmsh's documentation, "Node ordering"; meshio converts the same way).
fn vtk_order(vtk: u8) -> Option<&'static [usize]> {
    const HEX20: [usize; 20] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
    ];
    const HEX27: [usize; 27] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20,
        25, 26,
    ];
    const WEDGE15: [usize; 15] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11];
    const WEDGE18: [usize; 18] = [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11, 15, 17, 16];
    const PYRAMID13: [usize; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];
    Some(match vtk {
        cell_type::QUADRATIC_HEXAHEDRON => &HEX20,
        cell_type::TRIQUADRATIC_HEXAHEDRON => &HEX27,
        cell_type::QUADRATIC_WEDGE => &WEDGE15,
        cell_type::BIQUADRATIC_QUADRATIC_WEDGE => &WEDGE18,
        cell_type::QUADRATIC_PYRAMID => &PYRAMID13,
        _ => return None,
    })
}

impl Sections {
    pub(super) fn elements(&mut self, m: &mut Msh, line: usize) -> Result<(), ParseError> {
        self.desc.cells_line = line;
        if self.version == 2 {
            let n = m.c.count("the number of elements", 0)?;
            let n = m.bounded(n as u64, 8, "the number of elements", line)?;
            if m.binary {
                m.c.next_line();
                self.elements_v2_binary(m, n, line)?;
            } else {
                self.elements_v2_ascii(m, n)?;
            }
            if self.physical.iter().any(|&p| p != 0) {
                self.has_physical = true;
            }
        } else {
            self.elements_v4(m, line)?;
            if !self.entity_physical.is_empty() {
                self.has_physical = true;
            }
        }
        m.end("Elements")
    }

    /// 2.2 binary: blocks of `type, count, number of tags`, then per element its tag, its tags
    /// (the first is the physical group) and its nodes.
    fn elements_v2_binary(&mut self, m: &mut Msh, n: usize, line: usize) -> Result<(), ParseError> {
        let mut done = 0;
        while done < n {
            let ty = m.int("the element type")?;
            let count = m.int("the number of elements that follow")?;
            let ntags = m.int("the number of tags")?;
            let (vtk, nn) = element_type(ty)
                .ok_or_else(|| m.c.err(format!("unknown Gmsh element type {ty}")))?;
            if count <= 0 || ntags < 0 || done + count as usize > n {
                return Err(m.c.err(format!("element block of {count} elements with {ntags} tags does not fit the {n} elements declared")));
            }
            let count = m.bounded(count as u64, 4 * (1 + nn), "the element block", line)?;
            // Per element: its tag, its tags (the first is the physical group), its nodes.
            let width = 1 + ntags as usize + nn;
            let words = m.words(count.saturating_mul(width), 4, "the element block")?;
            let at = m.c.line;
            for e in words.chunks_exact(width) {
                let phys = if ntags > 0 { int_of(e[1]) } else { 0 };
                let nodes = e[width - nn..].iter().map(|&w| int_of(w) as u64);
                self.raw_elements.tags.extend(nodes);
                self.add_element(int_of(e[0]) as u64, phys, vtk, at);
            }
            done += count;
        }
        Ok(())
    }

    /// 2.2 ASCII: `tag type ntags tag… node…` per line. An element type VoRANG does not know
    /// is kept (as 255) with whatever nodes the line gives; it is skipped later. The lines are
    /// parsed on every core where they are plain ([`lines`]), else token by token.
    fn elements_v2_ascii(&mut self, m: &mut Msh, n: usize) -> Result<(), ParseError> {
        let row = |line: &[u8], out: &mut Vec<i64>| {
            let at = out.len();
            out.push(0);
            for t in lines::tokens(line) {
                match lines::int(t) {
                    Some(v) => out.push(v),
                    None => return false,
                }
            }
            out[at] = (out.len() - at - 1) as i64;
            out[at] > 0
        };
        if let Some(stream) = lines::parse_rows_with(&mut m.c, n, row) {
            let first_line = m.c.line + 1 - n;
            let mut rest = &stream[..];
            for k in 0..n {
                let (len, tail) = rest.split_first().expect("a row's count");
                let (nums, tail) = tail.split_at(*len as usize);
                self.element_v2(m, nums, first_line + k)?;
                rest = tail;
            }
            return Ok(());
        }
        for _ in 0..n {
            let (first, eline) = m.c.expect_token("an element")?;
            let rest = m.c.rest_of_line();
            let nums: Vec<i64> = std::iter::once(first)
                .chain(rest.split_whitespace())
                .map(|t| {
                    parse_int(t).ok_or_else(|| {
                        m.c.err_at(
                            eline,
                            format!("expected integers in an element line, found '{t}'"),
                        )
                    })
                })
                .collect::<Result<_, _>>()?;
            self.element_v2(m, &nums, eline)?;
        }
        Ok(())
    }

    /// One 2.2 ASCII element line's numbers (read at `eline`).
    fn element_v2(&mut self, m: &Msh, nums: &[i64], eline: usize) -> Result<(), ParseError> {
        if nums.len() < 3 {
            return Err(m.c.err_at(
                eline,
                "an element line needs a tag, a type and a number of tags",
            ));
        }
        let ntags = usize::try_from(nums[2].max(0)).unwrap_or(usize::MAX);
        if nums.len() - 3 < ntags {
            return Err(m
                .c
                .err_at(eline, "the element line is shorter than its number of tags"));
        }
        let nodes = &nums[3 + ntags..];
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
        let phys = if ntags > 0 { nums[3] } else { 0 };
        let tags = nodes.iter().map(|&x| x.max(0) as u64);
        self.raw_elements.tags.extend(tags);
        self.add_element(nums[0] as u64, phys, vtk, eline);
        Ok(())
    }

    /// 4.1: entity blocks of one element type; the physical group is the entity's.
    fn elements_v4(&mut self, m: &mut Msh, line: usize) -> Result<(), ParseError> {
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
            let bline = m.next_line_no();
            let dim = m.int("the entity dimension")?;
            let tag = m.int("the entity tag")?;
            let ty = m.int("the element type")?;
            let n = m.size("the number of elements in the block")?;
            let (vtk, nn) = element_type(ty)
                .ok_or_else(|| m.c.err_at(bline, format!("unknown Gmsh element type {ty}")))?;
            let n = m.bounded(
                n,
                2 * (1 + nn),
                "the number of elements in the block",
                bline,
            )?;
            let phys = self.entity_physical.get(&(dim, tag)).copied().unwrap_or(0);
            // Rows at once: binary words, or ASCII lines where they are plain.
            let rows = if m.binary {
                let size = m.size_t;
                Some(m.words(n.saturating_mul(1 + nn), size, "the elements of a block")?)
            } else {
                lines::parse_rows(&mut m.c, n, 1 + nn, uints)
            };
            if let Some(rows) = rows {
                // Binary data have no lines: every element is named at its block's.
                let first_line = if m.binary { bline } else { m.c.line + 1 - n };
                let step = usize::from(!m.binary);
                for (k, e) in rows.chunks_exact(1 + nn).enumerate() {
                    self.raw_elements.tags.extend_from_slice(&e[1..]);
                    self.add_element(e[0], phys, vtk, first_line + k * step);
                }
                continue;
            }
            for _ in 0..n {
                let eline = m.next_line_no();
                let id = m.size("an element tag")?;
                for _ in 0..nn {
                    let t = m.size("an element node")?;
                    self.raw_elements.tags.push(t);
                }
                self.add_element(id, phys, vtk, eline);
            }
        }
        Ok(())
    }

    /// One element: its tag, physical group, VTK type and line; its node tags have just been
    /// pushed onto `raw_elements.tags`.
    fn add_element(&mut self, tag: u64, physical: i64, vtk: u8, line: usize) {
        self.element_tags.push(tag);
        self.physical.push(physical);
        let raw = &mut self.raw_elements;
        if raw.offsets.is_empty() {
            raw.offsets.push(0);
        }
        raw.types.push(vtk);
        raw.offsets.push(raw.tags.len());
        raw.lines.push(line);
    }

    /// Node tags → node indices, into the description's cells (with the 10-node tetrahedron's
    /// last two nodes swapped into VTK order). A volume cell must name defined nodes; other
    /// cells are skipped later, so an unknown tag there becomes node 0.
    ///
    /// The tags are looked up on every core, straight into the cells' connectivity (one
    /// allocation of the final size); the elements' types and offsets move over as they are.
    /// Only the elements that hold an unknown tag (or an index too large for 32 bits, which
    /// looks the same) are looked at again one by one, in file order, so the first refused
    /// element is the one a serial reader meets.
    pub(super) fn connect_elements(&mut self, name: &str) -> Result<(), ParseError> {
        let RawElements {
            types,
            mut offsets,
            tags,
            lines,
        } = std::mem::take(&mut self.raw_elements);
        if offsets.is_empty() {
            offsets.push(0);
        }
        let index = &self.node_index;
        let mut nodes: Vec<u32> = tags
            .par_iter()
            .with_min_len(1 << 14)
            .map(|&t| {
                index
                    .get(t)
                    .map_or(UNKNOWN, |k| u32::try_from(k).unwrap_or(UNKNOWN))
            })
            .collect();
        if nodes.par_iter().any(|&k| k == UNKNOWN) {
            for (i, &vtk) in types.iter().enumerate() {
                let (from, to) = (offsets[i], offsets[i + 1]);
                if !nodes[from..to].contains(&UNKNOWN) {
                    continue;
                }
                for (k, &t) in nodes[from..to].iter_mut().zip(&tags[from..to]) {
                    if *k != UNKNOWN || index.get(t).is_some() {
                        continue;
                    }
                    if cell_type::volume_nodes(vtk).is_some() {
                        return Err(ParseError::new(
                            name,
                            lines[i],
                            format!(
                                "element {} refers to node tag {t}, which $Nodes does not define",
                                self.element_tags[i]
                            ),
                        ));
                    }
                    *k = 0;
                }
            }
        }
        drop(tags);
        for (i, &vtk) in types.iter().enumerate() {
            let order = vtk_order(vtk);
            if vtk != cell_type::QUADRATIC_TETRA && order.is_none() {
                continue;
            }
            let cell = &mut nodes[offsets[i]..offsets[i + 1]];
            if vtk == cell_type::QUADRATIC_TETRA {
                cell.swap(8, 9);
            }
            if let Some(order) = order
                && cell.len() == order.len()
            {
                // The Gmsh order kept on the stack (27 nodes at most: `vtk_order`).
                let mut gmsh = [0u32; 27];
                gmsh[..cell.len()].copy_from_slice(cell);
                for (n, &k) in cell.iter_mut().zip(order) {
                    *n = gmsh[k];
                }
            }
        }
        let cells = &mut self.desc.cells;
        cells.types = types;
        cells.offsets = offsets;
        cells.connectivity = nodes;
        Ok(())
    }
}
