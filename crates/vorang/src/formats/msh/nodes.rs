//! `$Entities` (4.1: the physical group of each geometric entity, which its elements inherit)
//! and `$Nodes` (tags and coordinates, in 2.2's flat list or 4.1's entity blocks). Nodes are
//! stored in file order and found by tag through `node_index`, since tags may be sparse.

use super::Sections;
use super::elements::uints;
use super::input::{Msh, int_word, word};
use crate::error::ParseError;
use crate::formats::lines;

/// A row of exactly three decimal numbers (coordinates).
fn floats3(line: &[u8], out: &mut [[f64; 3]]) -> bool {
    let mut t = lines::tokens(line);
    let mut num = || t.next().and_then(lines::float);
    match [num(), num(), num()] {
        [Some(x), Some(y), Some(z)] if t.at_end() => {
            out[0] = [x, y, z];
            true
        }
        _ => false,
    }
}

impl Sections {
    /// `$Entities` (4.1): points, curves, surfaces and volumes with their physical tags.
    pub(super) fn entities(&mut self, m: &mut Msh, line: usize) -> Result<(), ParseError> {
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
                        self.entity_physical.insert((dim as i64, tag), p);
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
        m.end("Entities")
    }

    pub(super) fn nodes(&mut self, m: &mut Msh, line: usize) -> Result<(), ParseError> {
        self.desc.points_line = line;
        if self.version == 2 {
            self.nodes_v2(m, line)?;
        } else {
            self.nodes_v4(m, line)?;
        }
        m.end("Nodes")
    }

    /// 2.2: `n`, then `tag x y z` per node.
    fn nodes_v2(&mut self, m: &mut Msh, line: usize) -> Result<(), ParseError> {
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
        self.desc.nodes.reserve(n);
        if m.binary {
            // Per node: an int tag and three doubles.
            let rows = m.records(n, 28, "the nodes", |r, swap| {
                let x = |k: usize| f64::from_bits(word(&r[4 + 8 * k..12 + 8 * k], swap));
                (int_word(&r[..4], swap), [x(0), x(1), x(2)])
            })?;
            for (tag, p) in rows {
                self.add_node(m, m.c.line, tag as u64, tag, p)?;
            }
            return Ok(());
        }
        if let Some(rows) = lines::parse_rows(&mut m.c, n, 1, |line, out| {
            let mut t = lines::tokens(line);
            let Some(tag) = t.next().and_then(lines::int) else {
                return false;
            };
            let mut num = || t.next().and_then(lines::float);
            match [num(), num(), num()] {
                [Some(x), Some(y), Some(z)] if t.at_end() => {
                    out[0] = (tag, [x, y, z]);
                    true
                }
                _ => false,
            }
        }) {
            let first_line = m.c.line + 1 - n;
            for (k, (tag, p)) in rows.into_iter().enumerate() {
                self.add_node(m, first_line + k, tag as u64, tag, p)?;
            }
            return Ok(());
        }
        for _ in 0..n {
            let tag = m.int("a node tag")?;
            let p = [m.double("x")?, m.double("y")?, m.double("z")?];
            // The tag as written (a negative one is named as such).
            self.add_node(m, m.c.line, tag as u64, tag, p)?;
        }
        Ok(())
    }

    /// 4.1: entity blocks, each its node tags and then their coordinates.
    fn nodes_v4(&mut self, m: &mut Msh, line: usize) -> Result<(), ParseError> {
        if m.binary {
            m.c.next_line();
        }
        let blocks = m.size("the number of entity blocks")?;
        let total = m.size("the number of nodes")?;
        m.size("the smallest node tag")?;
        m.size("the largest node tag")?;
        let blocks = m.bounded(blocks, 4, "the number of node blocks", line)?;
        let total = m.bounded(total, 8, "the number of nodes", line)?;
        self.desc.nodes.reserve(total);
        for _ in 0..blocks {
            let bline = m.next_line_no();
            let _dim = m.int("the entity dimension")?;
            let _tag = m.int("the entity tag")?;
            let parametric = m.int("the parametric flag")?;
            let n = m.size("the number of nodes in the block")?;
            let n = m.bounded(n, 8, "the number of nodes in the block", bline)?;
            if parametric != 0 {
                return Err(m.c.err_at(
                    bline,
                    "parametric node coordinates are not supported; save the mesh without them",
                ));
            }
            if m.binary {
                let size = m.size_t;
                let tags = m.words(n, size, "the node tags of a block")?;
                let xyz = m.words(3 * n, 8, "the node coordinates of a block")?;
                for (&tag, p) in tags.iter().zip(xyz.chunks_exact(3)) {
                    let p = [0, 1, 2].map(|k| f64::from_bits(p[k]));
                    self.add_node(m, m.c.line, tag, tag, p)?;
                }
                continue;
            }
            let tags = match lines::parse_rows(&mut m.c, n, 1, uints) {
                Some(tags) => tags,
                None => (0..n)
                    .map(|_| m.size("a node tag"))
                    .collect::<Result<_, _>>()?,
            };
            let coords = lines::parse_rows(&mut m.c, n, 1, floats3);
            if let Some(coords) = coords {
                let first_line = m.c.line + 1 - n;
                for (k, (&tag, p)) in tags.iter().zip(coords).enumerate() {
                    self.add_node(m, first_line + k, tag, tag, p)?;
                }
                continue;
            }
            for tag in tags {
                let p = [m.double("x")?, m.double("y")?, m.double("z")?];
                self.add_node(m, m.c.line, tag, tag, p)?;
            }
        }
        Ok(())
    }

    /// A node with tag `tag` (`shown` in messages, read at `line`), which must not repeat an
    /// earlier one.
    fn add_node(
        &mut self,
        m: &Msh,
        line: usize,
        tag: u64,
        shown: impl std::fmt::Display,
        p: [f64; 3],
    ) -> Result<(), ParseError> {
        if !self.node_index.insert(tag, self.desc.nodes.len()) {
            return Err(m.c.err_at(line, format!("node tag {shown} appears twice")));
        }
        self.desc.nodes.push(p);
        Ok(())
    }
}
