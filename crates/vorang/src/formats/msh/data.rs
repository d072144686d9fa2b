//! `$NodeData` and `$ElementData`: values by node or element tag, one array per section (named
//! by its first string tag). The values are kept by tag while the file is read and placed into
//! rows by [`arrays`] once every node and element is known, since data may come before the mesh
//! they describe and need not cover every node or element.

use super::tags::TagIndex;

use super::Sections;
use super::input::Msh;
use crate::error::ParseError;
use crate::formats::{Array, ArrayValues, MeshDescription};

/// One `$NodeData` or `$ElementData` section.
pub(super) struct Data {
    name: String,
    components: usize,
    /// Tag → values.
    entries: Vec<(u64, Vec<f64>)>,
    line: usize,
    on_nodes: bool,
}

impl Sections {
    /// `$NodeData` or `$ElementData` (`sec`): string, real and integer tags (the second and
    /// third integer tags are the components and the number of entries), then `tag value…`.
    pub(super) fn data_section(
        &mut self,
        m: &mut Msh,
        sec: &str,
        line: usize,
    ) -> Result<(), ParseError> {
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
                format!("{sec}: {comps} components and {count} entries: expected 1…9 components"),
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
            dname = format!("data{}", self.data.len());
        }
        self.data.push(Data {
            name: dname,
            components: comps,
            entries,
            line,
            on_nodes,
        });
        Ok(())
    }
}

/// The data sections as point and cell arrays, each value in the row of its tag (0 where a
/// section gives none). Element data that are all whole numbers in 0…255 become integers.
pub(super) fn arrays(
    name: &str,
    data: Vec<Data>,
    node_index: &TagIndex,
    element_tags: &[u64],
    desc: &MeshDescription,
) -> Result<(Vec<Array>, Vec<Array>), ParseError> {
    // Only built where element data need it.
    let element_index = if data.iter().any(|d| !d.on_nodes) {
        TagIndex::of(element_tags)
    } else {
        TagIndex::default()
    };
    let mut points = Vec::new();
    let mut cells = Vec::new();
    for d in data {
        let (index, n) = if d.on_nodes {
            (node_index, desc.nodes.len())
        } else {
            (&element_index, desc.cells.len())
        };
        let mut values = vec![0.0; n * d.components];
        for (tag, v) in &d.entries {
            let Some(k) = index.get(*tag) else {
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
    Ok((points, cells))
}
