//! XDMF 3 (`.xdmf`, `.xmf`): grids described in XML with their data in HDF5 files or in the
//! XML itself, with every time step (docs/formats.md, "XDMF").
//!
//! Two layouts matter. dolfinx writes the mesh once as a Uniform grid and, per function, a
//! Temporal collection whose grids pull the mesh in (`xi:include`) and add one Attribute at
//! their Time; meshio's time-series writer does the same with all fields in one collection. A
//! general file is a Uniform grid, or a Temporal collection of Uniform grids with their own
//! Topology and Geometry. VoRANG's steps are the distinct Times of all Temporal collections; a
//! step's grid is the first of its grids that has a mesh, and its arrays are the Attributes of
//! all its grids (the first of a name wins). Without a Temporal collection the file is one
//! step: its first Uniform grid.

mod data;
mod topology;
pub mod tree;

use std::path::Path;

use data::Items;
use tree::Node;

use super::{Array, FileStep, MeshDescription, Warning};
use crate::error::ParseError;

/// Whether a file's head is XDMF: an `<Xdmf` element near the start of an XML text.
pub fn sniff(head: &[u8]) -> bool {
    super::starts_after_space(head, b"<") && head.windows(5).any(|w| w == b"<Xdmf")
}

/// Step 0 of an XDMF file held in memory (its HDF5 files relative to `name`'s folder).
pub fn read(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    let root = tree::parse(bytes, name)?;
    let steps = step_grids(&root, name)?;
    describe(&root, &steps, 0, name)
}

/// The steps of the XDMF file at `path`.
pub fn steps(path: &Path, name: &str) -> Result<Vec<FileStep>, ParseError> {
    let bytes = read_file(path, name)?;
    let root = tree::parse(&bytes, name)?;
    Ok(step_grids(&root, name)?
        .into_iter()
        .enumerate()
        .map(|(index, s)| FileStep {
            time: s.time,
            file: path.to_path_buf(),
            index,
        })
        .collect())
}

/// Step `index` of the XDMF file at `path`.
pub fn read_step(path: &Path, name: &str, index: usize) -> Result<MeshDescription, ParseError> {
    let bytes = read_file(path, name)?;
    let root = tree::parse(&bytes, name)?;
    let steps = step_grids(&root, name)?;
    describe(&root, &steps, index, name)
}

fn read_file(path: &Path, name: &str) -> Result<Vec<u8>, ParseError> {
    std::fs::read(path).map_err(|e| ParseError::new(name, 0, e.to_string()))
}

/// One step: its time and the grids that make it.
struct StepGrids<'a> {
    time: f64,
    grids: Vec<&'a Node>,
}

/// The `<Domain>` of the file.
fn domain<'a>(root: &'a Node, name: &str) -> Result<&'a Node, ParseError> {
    if root.name != "Xdmf" {
        return Err(ParseError::new(
            name,
            root.line,
            format!("expected <Xdmf>, found <{}>", root.name),
        ));
    }
    root.first("Domain")
        .ok_or_else(|| ParseError::new(name, root.line, "<Xdmf> without a <Domain>"))
}

fn is_collection(g: &Node, kind: &str) -> bool {
    g.attr("GridType") == Some("Collection") && g.attr("CollectionType").unwrap_or("") == kind
}

/// A grid's `<Time Value="…">`.
fn time_of(g: &Node, name: &str) -> Result<Option<f64>, ParseError> {
    let Some(t) = g.first("Time") else {
        return Ok(None);
    };
    let Some(v) = t.attr("Value") else {
        return Ok(None);
    };
    v.trim()
        .parse::<f64>()
        .map(Some)
        .map_err(|_| ParseError::new(name, t.line, format!("Time Value=\"{v}\" is not a number")))
}

/// The steps of the file: the distinct times of the Temporal collections' grids (in order
/// of time; the grids of one time from every collection), or the first Uniform grid.
fn step_grids<'a>(root: &'a Node, name: &str) -> Result<Vec<StepGrids<'a>>, ParseError> {
    let domain = domain(root, name)?;
    let mut timed: Vec<(f64, &Node)> = Vec::new();
    let mut uniform = None;
    for g in domain.all("Grid") {
        if is_collection(g, "Temporal") {
            for (k, child) in g.all("Grid").enumerate() {
                let time = time_of(child, name)?.unwrap_or(k as f64);
                if !time.is_finite() {
                    return Err(ParseError::new(name, child.line, "the Time is not finite"));
                }
                timed.push((time, child));
            }
        } else if g.attr("GridType").is_none_or(|t| t == "Uniform") {
            uniform.get_or_insert(g);
        }
    }
    if timed.is_empty() {
        let g = uniform.ok_or_else(|| {
            ParseError::new(
                name,
                domain.line,
                "no Uniform grid and no Temporal collection in the <Domain>",
            )
        })?;
        return Ok(vec![StepGrids {
            time: time_of(g, name)?.unwrap_or(0.0),
            grids: vec![g],
        }]);
    }
    timed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut steps: Vec<StepGrids> = Vec::new();
    for (time, g) in timed {
        match steps.last_mut() {
            Some(last) if last.time == time => last.grids.push(g),
            _ => steps.push(StepGrids {
                time,
                grids: vec![g],
            }),
        }
    }
    Ok(steps)
}

/// The grid an `xi:include`'s xpointer (or a `Reference`'s path) names: `[@Name='X']`, the
/// k-th Uniform grid (`[@GridType='Uniform'][k]`), or the first Uniform grid of the Domain.
fn pointed_grid<'a>(domain: &'a Node, pointer: &str) -> Option<&'a Node> {
    let quoted = |key: &str| {
        let at = pointer.find(key)? + key.len();
        let rest = pointer[at..].trim_start_matches(['=', ' ']);
        let quote = rest.chars().next().filter(|c| *c == '\'' || *c == '"')?;
        let body = &rest[1..];
        Some(body[..body.find(quote)?].to_string())
    };
    let uniform = || {
        domain
            .all("Grid")
            .filter(|g| g.attr("GridType").is_none_or(|t| t == "Uniform"))
    };
    if let Some(name) = quoted("@Name") {
        return domain
            .all("Grid")
            .find(|g| g.attr("Name") == Some(name.as_str()));
    }
    if let Some(at) = pointer.find("[@GridType='Uniform'][") {
        let rest = &pointer[at + "[@GridType='Uniform'][".len()..];
        let k: usize = rest[..rest.find(']')?].trim().parse().ok()?;
        return uniform().nth(k.checked_sub(1)?);
    }
    uniform().next()
}

/// A grid's Topology or Geometry (`what`): its own, one its `xi:include` pulls in, or one a
/// `Reference` names.
fn part_of<'a>(domain: &'a Node, grid: &'a Node, what: &str) -> Option<&'a Node> {
    if let Some(own) = grid.first(what) {
        if own.attr("Reference").is_some() {
            let target = pointed_grid(domain, own.text.trim())?;
            return target.first(what);
        }
        return Some(own);
    }
    // The XInclude prefix is the writer's choice (`xi:include`, meshio's `ns0:include`).
    grid.children
        .iter()
        .filter(|c| c.name == "include" || c.name.ends_with(":include"))
        .filter_map(|inc| pointed_grid(domain, inc.attr("xpointer").unwrap_or("")))
        .find_map(|g| g.first(what))
}

/// The description of step `index`.
fn describe(
    root: &Node,
    steps: &[StepGrids],
    index: usize,
    name: &str,
) -> Result<MeshDescription, ParseError> {
    let domain = domain(root, name)?;
    let step = steps.get(index).ok_or_else(|| {
        ParseError::new(
            name,
            domain.line,
            format!("has {} steps, not step {index}", steps.len()),
        )
    })?;
    let mesh = step.grids.iter().find_map(|g| {
        Some((
            part_of(domain, g, "Topology")?,
            part_of(domain, g, "Geometry")?,
        ))
    });
    let Some((topology, geometry)) = mesh else {
        return Err(ParseError::new(
            name,
            step.grids[0].line,
            format!(
                "the grid of step {index} (t = {}) has no Topology and Geometry",
                step.time
            ),
        ));
    };
    let mut items = Items::new(name);
    let mut desc = MeshDescription {
        source: name.to_string(),
        format: "XDMF".into(),
        points_line: geometry.line,
        cells_line: topology.line,
        ..MeshDescription::default()
    };
    let (nodes, float) = topology::geometry(&mut items, geometry)?;
    desc.nodes = nodes;
    desc.float_coordinates = float;
    desc.cells = topology::cells(&mut items, topology, desc.nodes.len())?;
    for g in &step.grids {
        for a in g.all("Attribute") {
            add_attribute(&mut items, &mut desc, a)?;
        }
    }
    Ok(desc)
}

/// One `<Attribute>` as a point or cell array (other centres are skipped with a warning).
fn add_attribute(
    items: &mut Items,
    desc: &mut MeshDescription,
    a: &Node,
) -> Result<(), ParseError> {
    let name = a.attr("Name").unwrap_or("").to_string();
    if desc
        .point_arrays
        .iter()
        .chain(&desc.cell_arrays)
        .any(|x| x.name == name)
    {
        return Ok(());
    }
    let center = a.attr("Center").unwrap_or("Node");
    let (count, cell) = match center {
        "Node" => (desc.nodes.len(), false),
        "Cell" => (desc.cells.len(), true),
        other => {
            desc.warnings.push(Warning {
                file: items.source.to_string(),
                line: Some(a.line),
                message: format!("Attribute \"{name}\" has Center=\"{other}\": skipped (VoRANG reads Node and Cell data)"),
            });
            return Ok(());
        }
    };
    let item = a
        .first("DataItem")
        .ok_or_else(|| items.error(a.line, format!("Attribute \"{name}\" without a DataItem")))?;
    let data = items.read(item)?;
    let components = data.row();
    if data.values.len() != count * components {
        return Err(items.error(
            item.line,
            format!(
                "Attribute \"{name}\" (Center=\"{center}\") has {} values, expected {count} {} × {components}",
                data.values.len(),
                if cell { "cells" } else { "points" }
            ),
        ));
    }
    let array = Array {
        name,
        components,
        values: data.values,
        line: item.line,
    };
    if cell {
        desc.cell_arrays.push(array);
    } else {
        desc.point_arrays.push(array);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_STEPS: &str = r#"<?xml version="1.0"?>
<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">
<Domain>
<Grid Name="mesh" GridType="Uniform">
  <Topology TopologyType="Tetrahedron" NumberOfElements="1">
    <DataItem Dimensions="1 4" NumberType="Int" Format="XML">0 1 2 3</DataItem>
  </Topology>
  <Geometry GeometryType="XYZ">
    <DataItem Dimensions="4 3" Format="XML" Precision="8">0 0 0 1 0 0 0 1 0 0 0 1</DataItem>
  </Geometry>
</Grid>
<Grid Name="u" GridType="Collection" CollectionType="Temporal">
  <Grid Name="u" GridType="Uniform">
    <xi:include xpointer="xpointer(/Xdmf/Domain/Grid[@GridType='Uniform'][1]/*[self::Topology or self::Geometry])"/>
    <Time Value="0.5"/>
    <Attribute Name="u" AttributeType="Scalar" Center="Node">
      <DataItem Dimensions="4 1" Format="XML">5 6 7 8</DataItem>
    </Attribute>
  </Grid>
  <Grid Name="u" GridType="Uniform">
    <xi:include xpointer="xpointer(/Xdmf/Domain/Grid[@GridType='Uniform'][1]/*[self::Topology or self::Geometry])"/>
    <Time Value="0"/>
    <Attribute Name="u" AttributeType="Scalar" Center="Node">
      <DataItem Dimensions="4 1" Format="XML">1 2 3 4</DataItem>
    </Attribute>
  </Grid>
</Grid>
</Domain>
</Xdmf>
"#;

    #[test]
    fn temporal_grids_are_steps_in_time_order_on_the_included_mesh() {
        let d = read(TWO_STEPS.as_bytes(), "t.xdmf").unwrap();
        assert_eq!(d.nodes.len(), 4);
        assert_eq!(d.cells.len(), 1);
        assert_eq!(d.point_arrays[0].values.get(0), 1.0);
        let root = tree::parse(TWO_STEPS.as_bytes(), "t.xdmf").unwrap();
        let steps = step_grids(&root, "t.xdmf").unwrap();
        assert_eq!(steps.iter().map(|s| s.time).collect::<Vec<_>>(), [0.0, 0.5]);
        let second = describe(&root, &steps, 1, "t.xdmf").unwrap();
        assert_eq!(second.point_arrays[0].values.get(3), 8.0);
    }

    /// A one-step file: one Uniform grid with the given Topology and Geometry.
    fn uniform(topology: &str, geometry: &str) -> String {
        format!("<Xdmf><Domain><Grid Name=\"g\">\n{topology}\n{geometry}\n</Grid></Domain></Xdmf>")
    }

    #[test]
    fn geometries_xy_and_x_y_z_and_a_mixed_topology() {
        let mixed = r#"<Topology TopologyType="Mixed"><DataItem Dimensions="13" NumberType="Int">2 2 0 1 6 0 1 2 3 4 0 1 2</DataItem></Topology>"#;
        let split = r#"<Geometry GeometryType="X_Y_Z"><DataItem Dimensions="4">0 1 0 0</DataItem><DataItem Dimensions="4">0 0 1 0</DataItem><DataItem Dimensions="4">0 0 0 1</DataItem></Geometry>"#;
        let d = read(uniform(mixed, split).as_bytes(), "m.xdmf").unwrap();
        assert_eq!(d.nodes[3], [0.0, 0.0, 1.0]);
        assert!(d.float_coordinates);
        assert_eq!(d.cells.types, [3, 10, 5]);
        assert_eq!(d.cells.nodes(1), [0, 1, 2, 3]);
        let flat = r#"<Geometry GeometryType="XY"><DataItem Dimensions="4 2" Precision="8">0 0 1 0 0 1 1 1</DataItem></Geometry>"#;
        let d = read(uniform(mixed, flat).as_bytes(), "m.xdmf").unwrap();
        assert_eq!(d.nodes[3], [1.0, 1.0, 0.0]);
        assert!(!d.float_coordinates);
        let bad = mixed.replace("2 2 0 1 6", "2 2 0 1 99");
        let e = read(uniform(&bad, split).as_bytes(), "m.xdmf").unwrap_err();
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("unknown XDMF cell type 99"), "{e}");
        let cut = mixed.replace("13", "11").replace(" 4 0 1 2<", " 4 0<");
        let e = read(uniform(&cut, split).as_bytes(), "m.xdmf").unwrap_err();
        assert!(e.message.contains("ends inside the cell"), "{e}");
        let far = mixed.replace("6 0 1 2 3", "6 0 1 2 9");
        let e = read(uniform(&far, split).as_bytes(), "m.xdmf").unwrap_err();
        assert!(
            e.message.contains("node 9 is not one of the 4 points"),
            "{e}"
        );
    }

    #[test]
    fn wrong_counts_name_the_line() {
        let bad = TWO_STEPS.replace("1 2 3 4", "1 2 3");
        let e = read(bad.as_bytes(), "t.xdmf").unwrap_err();
        assert_eq!(e.line, 24, "{e}");
        assert!(e.message.contains("4 values, found 3"), "{e}");
    }
}
