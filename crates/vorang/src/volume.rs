//! The data volume (thesis: `VRxDataGrid`): a tetrahedral mesh together with its raw data and
//! field distributions, as loaded by the `volume` command and extended by `data [+]`.

use std::sync::Arc;

use crate::data::{DataType, ElementKind, Materials, RawData, ScalarType};
use crate::error::{Error, ParseError};
use crate::field::{Field, Interpolator, Origin, Support};
use crate::mesh::TetMesh;
use crate::mesh::edges::{NONE, edge_index, edges_of_cells};

/// The geometry of a volume: the validated mesh and the optional edge and triangle lists.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    pub mesh: TetMesh,
    /// The type the coordinates were stored with (written back the same way).
    pub coord_type: ScalarType,
    /// `FromTo` per edge (0-based), if the volume has edges. Edge direction matters for edge
    /// elements.
    pub edges: Option<Vec<[u32; 2]>>,
    /// Node triples per triangle (0-based), if the volume has triangles.
    pub triangles: Option<Vec<[u32; 3]>>,
    /// For each cell, its six edges (in [`crate::mesh::EDGE_NODES`] order) as indices into
    /// `edges`, with bit 31 set where the list directs the edge against the local order;
    /// [`NONE`] where the edge list lacks it. Present whenever `edges` is.
    pub tet_edges: Option<Vec<[u32; 6]>>,
}

/// Raw data and fields, with the element counts of the file they came from.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DataSet {
    pub materials: Option<Materials>,
    /// Counts as declared in the file, indexed by [`ElementKind::index`].
    pub counts: [Option<usize>; 5],
    /// The line of each count, for messages.
    pub count_lines: [Option<usize>; 5],
    pub raw: Vec<RawData>,
    pub fields: Vec<Field>,
}

/// A loaded volume.
#[derive(Debug, Clone, PartialEq)]
pub struct Volume {
    /// The file it was loaded from (as given).
    pub source: String,
    /// Shared, so that the steps of a time series with the same points and cells share one
    /// mesh with its adjacency and sort structures (docs/formats.md, "Time series").
    pub mesh: Arc<TetMesh>,
    pub coord_type: ScalarType,
    pub edges: Option<Vec<[u32; 2]>>,
    pub triangles: Option<Vec<[u32; 3]>>,
    pub data: DataSet,
    tet_edges: Option<Vec<[u32; 6]>>,
}

impl Volume {
    /// Assembles a volume and checks the fields that depend on the geometry (edge elements need
    /// every edge of every cell).
    pub fn new(source: String, geometry: Geometry, data: DataSet) -> Result<Volume, ParseError> {
        let vol = Volume {
            source,
            mesh: Arc::new(geometry.mesh),
            coord_type: geometry.coord_type,
            edges: geometry.edges,
            triangles: geometry.triangles,
            data,
            tet_edges: geometry.tet_edges,
        };
        for f in &vol.data.fields {
            vol.check_field(f)?;
        }
        Ok(vol)
    }

    fn check_field(&self, f: &Field) -> Result<(), ParseError> {
        let needs_edges = matches!(
            f.interpolator,
            Interpolator::EdgeElem | Interpolator::EdgeElemSar | Interpolator::HigherOrder
        );
        if needs_edges {
            let err = |msg: String| ParseError::new(&f.origin.file, f.origin.line, msg);
            let Some(te) = &self.tet_edges else {
                return Err(err(format!(
                    "{} needs the volume's edges: the grid has no 'Edges {{ int[2] FromTo }}' block",
                    f.interpolator.name()
                )));
            };
            if let Some((t, k)) = te
                .iter()
                .enumerate()
                .find_map(|(t, e)| e.iter().position(|&x| x == NONE).map(|k| (t, k)))
            {
                let [i, j] = crate::mesh::EDGE_NODES[k];
                let tet = self.mesh.tets()[t];
                return Err(err(format!(
                    "{} needs every edge of every tetrahedron in the Edges block; tetrahedron {} has no edge {}–{} there",
                    f.interpolator.name(),
                    t + 1,
                    tet[i] + 1,
                    tet[j] + 1
                )));
            }
        }
        Ok(())
    }

    /// A volume on `like`'s geometry (the same shared mesh, edges and triangles) with other
    /// data: a time step whose points and cells have not changed, which allocates only its
    /// fields (docs/formats.md, "Time series"). The fields are checked as [`Volume::new`] checks
    /// them.
    pub fn sharing_geometry(
        like: &Volume,
        source: String,
        data: DataSet,
    ) -> Result<Volume, ParseError> {
        let vol = Volume {
            source,
            mesh: Arc::clone(&like.mesh),
            coord_type: like.coord_type,
            edges: like.edges.clone(),
            triangles: like.triangles.clone(),
            data,
            tet_edges: like.tet_edges.clone(),
        };
        for f in &vol.data.fields {
            vol.check_field(f)?;
        }
        Ok(vol)
    }

    /// A volume without data around a validated mesh (coordinates written back as double).
    pub fn from_mesh(source: impl Into<String>, mesh: TetMesh) -> Volume {
        let mut data = DataSet::default();
        data.counts[ElementKind::Node.index()] = Some(mesh.node_count());
        data.counts[ElementKind::Tetrahedron.index()] = Some(mesh.tet_count());
        Volume {
            source: source.into(),
            mesh: Arc::new(mesh),
            coord_type: ScalarType::Double,
            edges: None,
            triangles: None,
            data,
            tet_edges: None,
        }
    }

    /// Adds a raw data block; its number of elements must match the volume. Returns its index.
    pub fn add_raw(&mut self, raw: RawData) -> Result<usize, Error> {
        let want = match raw.kind {
            ElementKind::Extra => raw.elements(),
            kind => self.count(kind).ok_or_else(|| {
                Error::Invalid(format!(
                    "{} given, but the volume lists no {}s",
                    kind.data_keyword(),
                    kind.noun()
                ))
            })?,
        };
        if raw.elements() != want || raw.values.len() != want * raw.ty.numbers() {
            return Err(Error::Invalid(format!(
                "{} needs {want} elements of {}, found {} numbers",
                raw.kind.data_keyword(),
                raw.ty,
                raw.values.len()
            )));
        }
        self.data.raw.push(raw);
        Ok(self.data.raw.len() - 1)
    }

    /// Declares a field over raw data blocks (checked as a file's `Field` line is). Returns its
    /// number.
    pub fn add_field(
        &mut self,
        name: Option<&str>,
        ty: DataType,
        interpolator: Interpolator,
        sources: &[usize],
    ) -> Result<usize, Error> {
        let origin = Origin {
            file: self.source.clone(),
            line: 0,
        };
        let field = Field::build(
            name.map(str::to_string),
            ty,
            None,
            interpolator,
            sources.to_vec(),
            &self.data.raw,
            self.data.materials.as_ref(),
            origin,
            &|k| format!("raw data block {}", sources[k]),
        )
        .map_err(Error::Invalid)?;
        self.check_field(&field)
            .map_err(|e| Error::Invalid(e.message))?;
        self.data.fields.push(field);
        Ok(self.data.fields.len() - 1)
    }

    /// Adds a scalar field interpolated linearly from one double value per node (the most
    /// common field: a FEM solution on the nodes). Returns its number.
    pub fn add_node_field(&mut self, name: Option<&str>, values: Vec<f64>) -> Result<usize, Error> {
        let ty = DataType::scalar(ScalarType::Double);
        let raw = self.add_raw(RawData {
            kind: ElementKind::Node,
            ty,
            denominator: None,
            values: crate::data::Values::F64(values),
        })?;
        self.add_field(name, ty, Interpolator::Linear, &[raw])
    }

    /// The element count of a kind in this volume (`None` if the grid does not have such
    /// elements listed).
    pub fn count(&self, kind: ElementKind) -> Option<usize> {
        match kind {
            ElementKind::Node => Some(self.mesh.node_count()),
            ElementKind::Tetrahedron => Some(self.mesh.tet_count()),
            ElementKind::Edge => self.edges.as_ref().map(Vec::len),
            ElementKind::Triangle => self.triangles.as_ref().map(Vec::len),
            ElementKind::Extra => None,
        }
    }

    /// A cell's six edges in [`crate::mesh::EDGE_NODES`] order: index into [`Volume::edges`]
    /// and whether the file directs the edge against the local order. `None` without edges.
    pub fn tet_edges(&self, cell: usize) -> Option<[(usize, bool); 6]> {
        self.support().tet_edges(cell)
    }

    /// What this volume's fields are evaluated on ([`Field::eval`]).
    pub fn support(&self) -> Support<'_> {
        Support {
            mesh: &self.mesh,
            cell_edges: self.tet_edges.as_deref(),
            raw: &self.data.raw,
            materials: self.data.materials.as_ref(),
        }
    }

    pub fn field(&self, n: usize) -> Option<&Field> {
        self.data.fields.get(n)
    }

    /// Loads the raw data and fields of a data-only file (`name`, for messages) onto this grid
    /// (`data file` replaces all fields, `data + file` appends). Counts must match the grid; on
    /// any error nothing changes.
    pub fn attach_dataset(
        &mut self,
        name: &str,
        mut data: DataSet,
        append: bool,
    ) -> Result<(), ParseError> {
        for kind in ElementKind::ALL {
            let Some(n) = data.counts[kind.index()] else {
                continue;
            };
            let line = data.count_lines[kind.index()].unwrap_or(1);
            let uses = data.raw.iter().any(|r| r.kind == kind);
            match self.count(kind) {
                Some(have) if have != n => {
                    return Err(ParseError::new(
                        name,
                        line,
                        format!(
                            "{} = {n}, but the loaded grid has {have} {}s",
                            kind.count_keyword(),
                            kind.noun()
                        ),
                    ));
                }
                None if uses && kind != ElementKind::Extra => {
                    return Err(ParseError::new(
                        name,
                        line,
                        format!(
                            "this file has {} but the loaded grid lists no {}s",
                            kind.data_keyword(),
                            kind.noun()
                        ),
                    ));
                }
                _ => {}
            }
        }
        if append {
            if let (Some(a), Some(b)) = (&self.data.materials, &data.materials)
                && a != b
            {
                return Err(ParseError::new(
                    name,
                    1,
                    "its Materials block differs from the loaded volume's; 'data +' cannot merge two different material tables",
                ));
            }
            let offset = self.data.raw.len();
            for f in &mut data.fields {
                for s in &mut f.sources {
                    *s += offset;
                }
            }
            let mut merged = self.data.clone();
            merged.materials = merged.materials.or(data.materials);
            merged.raw.append(&mut data.raw);
            merged.fields.append(&mut data.fields);
            let candidate = std::mem::replace(&mut self.data, merged);
            if let Err(e) = self.check_all_fields() {
                self.data = candidate;
                return Err(e);
            }
        } else {
            data.materials = data.materials.or_else(|| self.data.materials.clone());
            data.counts = self.data.counts;
            data.count_lines = self.data.count_lines;
            let previous = std::mem::replace(&mut self.data, data);
            if let Err(e) = self.check_all_fields() {
                self.data = previous;
                return Err(e);
            }
        }
        Ok(())
    }

    /// `data [+] FILE` for a file of another format (.vtu, .vtk, .msh): its mesh must be this
    /// grid's (same node and tetrahedron counts, same cells); its fields replace or join this
    /// volume's. On any error nothing changes.
    pub fn attach_fields_of(&mut self, other: Volume, append: bool) -> Result<(), ParseError> {
        let err = |msg: String| ParseError::new(&other.source, 1, msg);
        if other.mesh.node_count() != self.mesh.node_count()
            || other.mesh.tet_count() != self.mesh.tet_count()
        {
            return Err(err(format!(
                "its mesh has {} nodes and {} tetrahedra, but the loaded grid has {} and {}; 'data' needs the same mesh",
                other.mesh.node_count(),
                other.mesh.tet_count(),
                self.mesh.node_count(),
                self.mesh.tet_count()
            )));
        }
        if other.mesh.tets() != self.mesh.tets() {
            return Err(err(
                "its cells are not the loaded grid's cells (same counts, other nodes); 'data' needs the same mesh".into(),
            ));
        }
        let needs_edges = other.data.fields.iter().any(|f| {
            other.data.raw[f.sources[0]].kind == ElementKind::Edge
                || f.sources
                    .iter()
                    .any(|&s| other.data.raw[s].kind == ElementKind::Edge)
        });
        if needs_edges && (other.edges != self.edges || other.tet_edges != self.tet_edges) {
            return Err(err(
                "its fields live on edges (quadratic cells) that the loaded grid does not list the same way; load it with 'volume' instead".into(),
            ));
        }
        let mut data = other.data;
        if append {
            let offset = self.data.raw.len();
            for f in &mut data.fields {
                for s in &mut f.sources {
                    *s += offset;
                }
            }
            let mut merged = self.data.clone();
            merged.raw.append(&mut data.raw);
            merged.fields.append(&mut data.fields);
            self.data = merged;
        } else {
            data.materials = self.data.materials.clone();
            data.counts = self.data.counts;
            data.count_lines = self.data.count_lines;
            self.data = data;
        }
        Ok(())
    }

    fn check_all_fields(&self) -> Result<(), ParseError> {
        self.data
            .fields
            .iter()
            .try_for_each(|f| self.check_field(f))
    }

    /// Per component: the smallest and largest value of field `n`, sampled at every cell's
    /// corners and centroid (exact for Linear and Constant fields).
    pub fn field_range(&self, n: usize) -> Option<Vec<(f64, f64)>> {
        let f = self.field(n)?;
        let k = f.components();
        let mut range = vec![(f64::INFINITY, f64::NEG_INFINITY); k];
        let mut out = vec![0.0; k];
        let samples: [[f64; 4]; 5] = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [0.25; 4],
        ];
        let on = self.support();
        for cell in 0..self.mesh.tet_count() {
            let corners = self.mesh.corners(cell);
            for l in &samples {
                let p = [0, 1, 2].map(|d| (0..4).map(|i| l[i] * corners[i][d]).sum());
                f.eval(&on, cell, l, p, &mut out);
                for (r, &v) in range.iter_mut().zip(&out) {
                    r.0 = r.0.min(v);
                    r.1 = r.1.max(v);
                }
            }
        }
        Some(range)
    }
}

/// The cells of `vol` where Constant field `field` is not zero (any component), with the nodes,
/// edges, triangles and data they use, renumbered in their original order (`save_subset`).
pub fn subset(vol: &Volume, field: usize) -> Result<Volume, Error> {
    let f = vol.field(field).ok_or_else(|| {
        Error::Invalid(format!(
            "save_subset: there is no field {field} (the volume has {} field{})",
            vol.data.fields.len(),
            if vol.data.fields.len() == 1 { "" } else { "s" }
        ))
    })?;
    if f.interpolator != Interpolator::Constant {
        return Err(Error::Invalid(format!(
            "save_subset: field {field} is {}; the mask must be a Constant (per-cell) field",
            f.interpolator.name()
        )));
    }
    let mask = &vol.data.raw[f.sources[0]];
    let n = mask.ty.numbers();
    let cells: Vec<u32> = (0..vol.mesh.tet_count())
        .filter(|&t| (0..n).any(|c| mask.values.get(t * n + c) != 0.0))
        .map(|t| t as u32)
        .collect();
    if cells.is_empty() {
        return Err(Error::Invalid(format!(
            "save_subset: field {field} is zero on every cell; the subset would be empty"
        )));
    }
    select(vol, cells, None).map_err(|e| Error::Invalid(format!("save_subset: {e}")))
}

/// An order of a volume's nodes (by their numbers), for [`select`].
pub type NodeOrder<'a> = &'a dyn Fn(u32, u32) -> std::cmp::Ordering;

/// The cells `cells` of `vol` (in that order), with the nodes, edges, triangles and data they
/// use. The nodes keep their original order, or are numbered in `order` (a rank's piece of a
/// distributed frame numbers them by a key all ranks share, so that a face between two pieces
/// gives both the same depths, docs/distributed.md); edges and triangles keep theirs.
pub fn select(vol: &Volume, cells: Vec<u32>, order: Option<NodeOrder>) -> Result<Volume, Error> {
    let tets = vol.mesh.tets();
    // Old → new numbering of the nodes, edges and triangles the kept cells use.
    let renumber = |used: Vec<bool>| -> (Vec<u32>, Vec<u32>) {
        let mut map = vec![NONE; used.len()];
        let mut kept = Vec::new();
        for (i, u) in used.into_iter().enumerate() {
            if u {
                map[i] = kept.len() as u32;
                kept.push(i as u32);
            }
        }
        (map, kept)
    };
    let mut used_nodes = vec![false; vol.mesh.node_count()];
    for &t in &cells {
        for n in tets[t as usize] {
            used_nodes[n as usize] = true;
        }
    }
    let (mut node_map, mut kept_nodes) = renumber(used_nodes);
    if let Some(order) = order {
        kept_nodes.sort_by(|&a, &b| order(a, b));
        for (i, &n) in kept_nodes.iter().enumerate() {
            node_map[n as usize] = i as u32;
        }
    }
    let nodes: Vec<[f64; 3]> = kept_nodes
        .iter()
        .map(|&n| vol.mesh.nodes()[n as usize])
        .collect();
    let new_tets: Vec<[u32; 4]> = cells
        .iter()
        .map(|&t| tets[t as usize].map(|n| node_map[n as usize]))
        .collect();

    let (edges, kept_edges) = match (&vol.edges, &vol.tet_edges) {
        (Some(list), Some(te)) => {
            let mut used = vec![false; list.len()];
            for &t in &cells {
                for &e in &te[t as usize] {
                    if e != NONE {
                        used[(e & !(1 << 31)) as usize] = true;
                    }
                }
            }
            let (_, kept) = renumber(used);
            let new: Vec<[u32; 2]> = kept
                .iter()
                .map(|&e| list[e as usize].map(|n| node_map[n as usize]))
                .collect();
            (Some(new), kept)
        }
        _ => (None, Vec::new()),
    };
    let (triangles, kept_tris) = match &vol.triangles {
        Some(list) => {
            let mut faces = std::collections::HashSet::new();
            for &t in &cells {
                for f in crate::mesh::FACE_NODES {
                    let mut k = f.map(|i| tets[t as usize][i]);
                    k.sort_unstable();
                    faces.insert(k);
                }
            }
            let used: Vec<bool> = list
                .iter()
                .map(|t| {
                    let mut k = *t;
                    k.sort_unstable();
                    faces.contains(&k)
                })
                .collect();
            let (_, kept) = renumber(used);
            let new: Vec<[u32; 3]> = kept
                .iter()
                .map(|&i| list[i as usize].map(|n| node_map[n as usize]))
                .collect();
            (Some(new), kept)
        }
        None => (None, Vec::new()),
    };

    let mut data = vol.data.clone();
    for r in &mut data.raw {
        let keep = match r.kind {
            ElementKind::Node => &kept_nodes,
            ElementKind::Tetrahedron => &cells,
            ElementKind::Edge => &kept_edges,
            ElementKind::Triangle => &kept_tris,
            ElementKind::Extra => continue,
        };
        r.values = r.values.select(r.ty.numbers(), keep);
    }
    for kind in ElementKind::ALL {
        data.counts[kind.index()] = match kind {
            ElementKind::Node => Some(nodes.len()),
            ElementKind::Tetrahedron => Some(cells.len()),
            ElementKind::Edge => edges.as_ref().map(Vec::len),
            ElementKind::Triangle => triangles.as_ref().map(Vec::len),
            ElementKind::Extra => data.counts[kind.index()],
        };
    }
    let mesh = TetMesh::new(nodes, new_tets).map_err(|e| Error::Invalid(e.to_string()))?;
    let tet_edges = edges.as_ref().map(|list| {
        // A subset of a valid edge list has no repeated pairs.
        let index = edge_index(list).unwrap_or_default();
        edges_of_cells(&mesh, list, &index)
    });
    let geometry = Geometry {
        mesh,
        coord_type: vol.coord_type,
        edges,
        triangles,
        tet_edges,
    };
    Volume::new(vol.source.clone(), geometry, data).map_err(Error::from)
}

/// A jittered Kuhn box in the unit cube with about `tets` cells and one smooth scalar node field
/// (float, values in [0, 1]): the benchmark and test volume.
pub fn jittered_box(tets: usize, jitter: f64, seed: u64) -> Volume {
    jittered_box_with_holes(tets, jitter, seed, 0.0)
}

/// [`jittered_box`] with each cell removed with probability `holes` (deterministic for a seed):
/// a non-convex mesh with cavities and tunnels, as meshes with excluded regions are.
pub fn jittered_box_with_holes(tets: usize, jitter: f64, seed: u64, holes: f64) -> Volume {
    let n = crate::mesh::generate::cubes_for(tets);
    let (nodes, mut cells) = crate::mesh::generate::kuhn_box([n, n, n], [1.0; 3], jitter, seed);
    if holes > 0.0 {
        let mut rng = crate::mesh::generate::SplitMix64(seed ^ 0x005e_ed0f_4013);
        cells.retain(|_| rng.next_f64() >= holes);
    }
    let values: Vec<f32> = nodes.iter().map(|&p| smooth_scalar(p) as f32).collect();
    // A Kuhn box with jitter ≤ 0.15 is always a valid mesh (checked by the generator's tests).
    let mesh = TetMesh::new(nodes, cells)
        .unwrap_or_else(|e| unreachable!("generated mesh is invalid: {e}"));
    let mut vol = Volume::from_mesh(
        format!("jittered box ({} tetrahedra)", mesh.tet_count()),
        mesh,
    );
    let raw = RawData {
        kind: ElementKind::Node,
        ty: DataType::scalar(ScalarType::Float),
        denominator: None,
        values: crate::data::Values::F32(values),
    };
    let r = vol.data.raw.len();
    vol.data.raw.push(raw);
    vol.data.fields.push(Field {
        name: Some("smooth".into()),
        ty: DataType::scalar(ScalarType::Float),
        denominator: None,
        interpolator: Interpolator::Linear,
        sources: vec![r],
        origin: Origin {
            file: vol.source.clone(),
            line: 0,
        },
    });
    vol
}

/// A smooth function on the unit cube with values in [0, 1].
pub fn smooth_scalar(p: [f64; 3]) -> f64 {
    let [x, y, z] = p;
    0.5 + 0.25
        * ((3.0 * x + 0.4).sin() * (2.0 * y + 0.1).cos() + (2.5 * z + 0.3).sin() * (1.5 * x).cos())
}
