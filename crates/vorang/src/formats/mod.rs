//! Mesh file formats as codecs: one module per format, each producing the same format-neutral
//! [`MeshDescription`] (nodes, cells with VTK cell types, named point and cell arrays), and one
//! registry ([`FORMATS`]) that maps content (magic bytes, header) and file-name extension to a
//! reader and a writer. [`Volume`]s are built from a description alone ([`build`]), so a new
//! format is one new file and one table line; nothing else learns about it.
//!
//! HyperMesh, the thesis's own format, keeps its dedicated reader ([`crate::formats::hypermesh`]): it
//! carries more than a description can (edges, triangles, materials, edge-element and
//! analytic fields, denominators), and its behaviour and messages are fixed by the thesis (appendix B) and docs/formats.md. The
//! registry lists it so that detection and "expected one of" messages cover every format.
//!
//! Format detection looks at the content first (`<VTKFile` for VTK XML — its `type` tells a
//! collection (`Collection`, `PUnstructuredGrid`, `vtkMultiBlockDataSet`) from a `.vtu` —,
//! `"file-series-version"` for ParaView's `.series`, `# vtk DataFile` for legacy VTK,
//! `$MeshFormat` for Gmsh, `# HyperMesh` for HyperMesh, `<Xdmf` for XDMF, netCDF's `CDF\x01` and
//! `CDF\x02` or HDF5 with Exodus's global attributes for Exodus II, HDF5 naming `VTKHDF` for
//! VTKHDF); the extension only decides when the content is not recognised (an HDF5 file whose
//! first 4 KiB do not say what it holds, usually), so a mis-named file still loads and a file
//! whose content no reader recognises gets a clear error naming the formats tried.
//!
//! Exodus II, XDMF and VTKHDF files hold time steps themselves: their readers list a file's
//! steps and read one ([`FileStep`]), and [`collection::multi`] makes them a series, as the
//! collections are.

pub mod build;
pub mod collection;
pub mod exodus;
pub mod hdf;
pub mod hypermesh;
pub mod lagrange;
pub mod layout;
mod lines;
pub mod msh;
mod text;
pub mod vtk_legacy;
pub mod vtkhdf;
pub mod vtu;
pub mod xdmf;

use std::path::Path;

use crate::error::{Error, ParseError, Warning};
use crate::volume::Volume;

/// VTK cell type numbers (the ones VoRANG turns into tetrahedra, and a few it names in
/// warnings). Gmsh element types are translated to these by the `.msh` reader.
pub mod cell_type {
    use super::lagrange::Shape;

    pub const VERTEX: u8 = 1;
    pub const LINE: u8 = 3;
    pub const TRIANGLE: u8 = 5;
    pub const QUAD: u8 = 9;
    pub const TETRA: u8 = 10;
    pub const VOXEL: u8 = 11;
    pub const HEXAHEDRON: u8 = 12;
    pub const WEDGE: u8 = 13;
    pub const PYRAMID: u8 = 14;
    pub const QUADRATIC_TETRA: u8 = 24;
    pub const QUADRATIC_HEXAHEDRON: u8 = 25;
    pub const QUADRATIC_WEDGE: u8 = 26;
    pub const QUADRATIC_PYRAMID: u8 = 27;
    pub const TRIQUADRATIC_HEXAHEDRON: u8 = 29;
    pub const BIQUADRATIC_QUADRATIC_WEDGE: u8 = 32;
    pub const POLYHEDRON: u8 = 42;
    pub const LAGRANGE_TETRAHEDRON: u8 = 71;
    pub const LAGRANGE_HEXAHEDRON: u8 = 72;
    pub const LAGRANGE_WEDGE: u8 = 73;
    pub const LAGRANGE_PYRAMID: u8 = 74;

    /// Number of nodes of the volume cell types with a fixed number of nodes, `None` for the
    /// others (see [`is_volume`] and [`node_count_problem`]).
    pub fn volume_nodes(t: u8) -> Option<usize> {
        match t {
            TETRA => Some(4),
            VOXEL | HEXAHEDRON => Some(8),
            WEDGE => Some(6),
            PYRAMID => Some(5),
            QUADRATIC_TETRA => Some(10),
            QUADRATIC_HEXAHEDRON => Some(20),
            QUADRATIC_WEDGE => Some(15),
            QUADRATIC_PYRAMID => Some(13),
            TRIQUADRATIC_HEXAHEDRON => Some(27),
            BIQUADRATIC_QUADRATIC_WEDGE => Some(18),
            _ => None,
        }
    }

    /// Whether cells of type `t` are volume cells VoRANG renders (with a fixed number of nodes,
    /// Lagrange cells of any degree, polyhedra).
    pub fn is_volume(t: u8) -> bool {
        volume_nodes(t).is_some() || t == POLYHEDRON || Shape::of(t).is_some()
    }

    /// What is wrong with a volume cell of type `t` having `n` nodes ("needs 8 nodes"), `None`
    /// if nothing is (or if `t` is no volume cell). A polyhedron lists its distinct points.
    pub fn node_count_problem(t: u8, n: usize) -> Option<String> {
        if let Some(need) = volume_nodes(t) {
            return (n != need).then(|| format!("needs {need} nodes"));
        }
        if let Some(shape) = Shape::of(t) {
            return shape.degree(n).is_none().then(|| {
                format!(
                    "needs the node count of a degree (for degrees 1, 2, 3: {})",
                    shape.counts()
                )
            });
        }
        (t == POLYHEDRON && n < 4).then(|| "needs at least 4 points".to_string())
    }

    /// A readable name for messages.
    pub fn name(t: u8) -> String {
        match t {
            VERTEX => "vertex".into(),
            LINE => "line".into(),
            TRIANGLE => "triangle".into(),
            QUAD => "quad".into(),
            TETRA => "tetrahedron".into(),
            VOXEL => "voxel".into(),
            HEXAHEDRON => "hexahedron".into(),
            WEDGE => "wedge".into(),
            PYRAMID => "pyramid".into(),
            QUADRATIC_TETRA => "quadratic tetrahedron".into(),
            QUADRATIC_HEXAHEDRON => "quadratic hexahedron".into(),
            QUADRATIC_WEDGE => "quadratic wedge".into(),
            QUADRATIC_PYRAMID => "quadratic pyramid".into(),
            TRIQUADRATIC_HEXAHEDRON => "triquadratic hexahedron".into(),
            BIQUADRATIC_QUADRATIC_WEDGE => "biquadratic-quadratic wedge".into(),
            POLYHEDRON => "polyhedron".into(),
            LAGRANGE_TETRAHEDRON => "Lagrange tetrahedron".into(),
            LAGRANGE_HEXAHEDRON => "Lagrange hexahedron".into(),
            LAGRANGE_WEDGE => "Lagrange wedge".into(),
            LAGRANGE_PYRAMID => "Lagrange pyramid".into(),
            255 => "higher-order element VoRANG does not read".into(),
            other => format!("VTK cell type {other}"),
        }
    }
}

/// The values of one named array, element-major then component.
#[derive(Debug, Clone, PartialEq)]
pub enum ArrayValues {
    /// Any integer type of the file.
    Int(Vec<i64>),
    F32(Vec<f32>),
    F64(Vec<f64>),
}

impl ArrayValues {
    pub fn len(&self) -> usize {
        match self {
            ArrayValues::Int(v) => v.len(),
            ArrayValues::F32(v) => v.len(),
            ArrayValues::F64(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn get(&self, i: usize) -> f64 {
        match self {
            ArrayValues::Int(v) => v[i] as f64,
            ArrayValues::F32(v) => f64::from(v[i]),
            ArrayValues::F64(v) => v[i],
        }
    }
}

/// A named point or cell array.
#[derive(Debug, Clone, PartialEq)]
pub struct Array {
    pub name: String,
    pub components: usize,
    pub values: ArrayValues,
    /// Where it was declared (1-based line; for binary files the line of the header that names
    /// it), for messages.
    pub line: usize,
}

impl Array {
    /// Number of elements (points or cells) it holds values for.
    pub fn elements(&self) -> usize {
        self.values.len() / self.components.max(1)
    }
}

/// Cells as VTK stores them: a type per cell and a flat connectivity list, cell `i` using
/// `connectivity[offsets[i]..offsets[i + 1]]` (so `offsets` has one entry more than `types`).
/// A polyhedron (VTK 42) lists its distinct points there and its faces in [`Faces`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Cells {
    pub types: Vec<u8>,
    pub offsets: Vec<usize>,
    /// 0-based node indices (32 bits, as every mesh VoRANG builds: half the memory of 64-bit
    /// indices while a large file is read). An index that does not fit is stored as
    /// `u32::MAX`, which is out of range for every mesh and reported as such.
    pub connectivity: Vec<u32>,
    /// The faces of the polyhedra.
    pub faces: Faces,
}

impl Cells {
    pub fn len(&self) -> usize {
        self.types.len()
    }

    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// The nodes of cell `i`.
    pub fn nodes(&self, i: usize) -> &[u32] {
        &self.connectivity[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Appends one cell.
    pub fn push(&mut self, ty: u8, nodes: &[u64]) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.types.push(ty);
        self.connectivity
            .extend(nodes.iter().map(|&n| u32::try_from(n).unwrap_or(u32::MAX)));
        self.offsets.push(self.connectivity.len());
    }

    /// Appends a polyhedron given as VTK's face stream, as legacy `.vtk` files and PyVista
    /// hold it: the number of faces, then each face as its number of points and its points.
    /// Its points are the distinct points of its faces. An error says what does not add up.
    pub fn push_face_stream(&mut self, stream: &[i64]) -> Result<(), String> {
        let faces = parse_face_stream(stream)?;
        let mut points: Vec<u32> = faces.iter().flatten().copied().collect();
        points.sort_unstable();
        points.dedup();
        let points: Vec<u64> = points.into_iter().map(u64::from).collect();
        self.push(cell_type::POLYHEDRON, &points);
        self.faces
            .push(self.len() - 1, faces.iter().map(Vec::as_slice));
        Ok(())
    }
}

/// The faces of a face stream (see [`Cells::push_face_stream`]).
pub(crate) fn parse_face_stream(stream: &[i64]) -> Result<Vec<Vec<u32>>, String> {
    let count = |at: usize, what: &str| -> Result<usize, String> {
        let v = stream.get(at).copied().ok_or_else(|| {
            format!(
                "the face stream ends after {} numbers, where {what} should follow",
                stream.len()
            )
        })?;
        usize::try_from(v)
            .ok()
            .filter(|&n| n <= stream.len())
            .ok_or_else(|| {
                format!(
                    "{what} is {v}, which the stream of {} numbers cannot hold",
                    stream.len()
                )
            })
    };
    let n = count(0, "the number of faces")?;
    let mut faces = Vec::with_capacity(n);
    let mut at = 1;
    for f in 0..n {
        let k = count(at, &format!("the number of points of face {}", f + 1))?;
        let ids = stream.get(at + 1..at + 1 + k).ok_or_else(|| {
            format!(
                "face {} has {k} points, but the face stream ends after {} numbers",
                f + 1,
                stream.len()
            )
        })?;
        let face = ids
            .iter()
            .map(|&v| u32::try_from(v).map_err(|_| format!("face {} refers to point {v}", f + 1)))
            .collect::<Result<Vec<u32>, String>>()?;
        faces.push(face);
        at += 1 + k;
    }
    if at != stream.len() {
        return Err(format!(
            "the {n} faces use {at} numbers of the face stream, but it has {}",
            stream.len()
        ));
    }
    Ok(faces)
}

/// The faces of the polyhedra among [`Cells`] (VTK ≥ 9.4 keeps them so): each face a list of
/// 0-based node indices, each polyhedron a run of faces.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Faces {
    /// The polyhedra in cell order: the cell's index and its first face; its faces run to the
    /// next polyhedron's first face (or to the last face).
    pub cells: Vec<(usize, usize)>,
    /// Face `f` uses `nodes[offsets[f]..offsets[f + 1]]` (empty, or starting with 0).
    pub offsets: Vec<usize>,
    pub nodes: Vec<u32>,
}

impl Faces {
    /// Number of faces.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The faces of cell `i`, `None` if it has none.
    pub fn of(&self, i: usize) -> Option<impl Iterator<Item = &[u32]>> {
        let k = self.cells.binary_search_by_key(&i, |c| c.0).ok()?;
        let end = self.cells.get(k + 1).map_or(self.len(), |c| c.1);
        Some((self.cells[k].1..end).map(|f| &self.nodes[self.offsets[f]..self.offsets[f + 1]]))
    }

    /// Appends the faces of cell `i`, which comes after every cell appended before.
    pub fn push<'a>(&mut self, i: usize, faces: impl IntoIterator<Item = &'a [u32]>) {
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.cells.push((i, self.len()));
        for f in faces {
            self.nodes.extend_from_slice(f);
            self.offsets.push(self.nodes.len());
        }
    }
}

/// What every reader produces: a mesh with named arrays, independent of the file format.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshDescription {
    /// The file name as given, for messages.
    pub source: String,
    /// The format's name, for `vorang info`.
    pub format: String,
    pub nodes: Vec<[f64; 3]>,
    /// Whether every coordinate came from 32-bit floats (written back that way).
    pub float_coordinates: bool,
    pub cells: Cells,
    /// Point arrays in file order.
    pub point_arrays: Vec<Array>,
    /// Cell arrays in file order (one value per cell of [`Cells`], all cell types).
    pub cell_arrays: Vec<Array>,
    /// Dataset-level arrays of any length (VTK `<FieldData>`): only those VoRANG writes
    /// ([`layout`]) are read.
    pub field_arrays: Vec<Array>,
    /// The line of the points and of the cells, for messages about them.
    pub points_line: usize,
    pub cells_line: usize,
    pub warnings: Vec<Warning>,
}

/// One time step of a file that holds several (Exodus II, XDMF, VTKHDF): its time, the file
/// that holds it (an Exodus continuation file when the mesh changed), and its number inside
/// that file. The time-series model ([`collection::Series`]) loads steps by these.
#[derive(Debug, Clone, PartialEq)]
pub struct FileStep {
    pub time: f64,
    pub file: std::path::PathBuf,
    pub index: usize,
}

/// A reader: a whole file's bytes and its name (for messages) to a description.
pub type ReadFn = fn(&[u8], &str) -> Result<MeshDescription, ParseError>;

/// A writer: a volume to a file (the options choose HyperMesh's encoding and layout; other
/// formats have one way of writing). Returns warnings about what the format cannot hold.
pub type WriteFn =
    fn(&Volume, &Path, crate::formats::hypermesh::WriteOptions) -> Result<Vec<Warning>, Error>;

/// A volume with the warnings of reading it.
pub type Loaded = (Volume, Vec<Warning>);

/// What a file holds, with the warnings of reading it.
pub type DescribedFile = (Described, Vec<Warning>);

/// What a file holds, for `vorang info`. Made once per file: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
pub enum Described {
    /// A grid with its data; `label` names the format (e.g. `VTK XML UnstructuredGrid`,
    /// `HyperMesh ASCII 0.7`).
    Volume { volume: Volume, label: String },
    /// Data without a grid (HyperMesh data-only files, for `data`): the file's name, its label
    /// and its data.
    Data {
        name: String,
        label: String,
        data: crate::volume::DataSet,
    },
    /// A collection ([`collection::Series`]): its step 0, and per field of step 0 its range
    /// over every step.
    Series {
        volume: Volume,
        series: collection::Series,
        ranges: collection::FieldRanges,
    },
}

/// One registry entry: how to recognise a format and everything VoRANG does with its files.
pub struct Format {
    pub name: &'static str,
    /// File-name extensions (lower case, without the dot).
    pub extensions: &'static [&'static str],
    /// Whether the first bytes of a file are this format.
    pub sniff: fn(&[u8]) -> bool,
    /// The format-neutral description of a file held in memory, for the formats read through
    /// one (`None` for HyperMesh, which carries more than a description can: edges, triangles,
    /// materials, edge-element and analytic fields).
    pub read: Option<ReadFn>,
    /// `volume FILE`: the volume of a file.
    pub load: fn(&Path) -> Result<Loaded, Error>,
    /// The volume of a file held in memory (`name` labels messages).
    pub load_bytes: fn(&[u8], &str) -> Result<Loaded, ParseError>,
    /// `data ?+? FILE`: `vol` with the file's fields replacing (or, `append`, added to) its own.
    pub load_data: fn(&Volume, &Path, bool) -> Result<Loaded, Error>,
    /// `vorang info FILE`: what the file holds.
    pub describe: fn(&Path) -> Result<DescribedFile, Error>,
    /// Writes a volume in this format; `None` for formats VoRANG only reads.
    pub write: Option<WriteFn>,
}

impl Format {
    /// Whether [`save_volume`] can write it.
    pub fn writable(&self) -> bool {
        self.write.is_some()
    }
}

/// The entry of a format read through a [`MeshDescription`]: every operation is the
/// description's reader followed by the one builder ([`build::volume`]).
macro_rules! described_format {
    ($name:expr, $extensions:expr, $sniff:expr, $read:expr, $write:expr) => {
        Format {
            name: $name,
            extensions: $extensions,
            sniff: $sniff,
            read: Some($read),
            load: |path| load_described(path, $read),
            load_bytes: |bytes, name| build::volume($read(bytes, name)?),
            load_data: |vol, path, append| {
                let (other, warnings) = load_described(path, $read)?;
                let mut next = vol.clone();
                next.attach_fields_of(other, append)?;
                Ok((next, warnings))
            },
            describe: |path| {
                let desc = $read(&read_bytes_of(path)?, &path.display().to_string())?;
                let label = desc.format.clone();
                let (volume, warnings) = build::volume(desc)?;
                Ok((Described::Volume { volume, label }, warnings))
            },
            write: $write,
        }
    };
}

/// Every format, HyperMesh first (the fallback for unknown extensions when writing, and for
/// text no other format recognises when reading: its reader reports on the title line). The
/// collections come before `.vtu`, whose content test takes any VTK XML file.
pub const FORMATS: &[Format] = &[
    hypermesh::FORMAT,
    collection::PVD,
    collection::PVTU,
    collection::VTM,
    collection::SERIES,
    collection::VTKHDF,
    collection::EXODUS,
    collection::XDMF,
    described_format!(
        "VTK XML UnstructuredGrid",
        &["vtu"],
        vtu::sniff,
        vtu::read,
        Some(|vol, path, _| vtu::save(vol, path))
    ),
    described_format!(
        "legacy VTK",
        &["vtk"],
        vtk_legacy::sniff,
        vtk_legacy::read,
        None
    ),
    described_format!("Gmsh", &["msh"], msh::sniff, msh::read, None),
];

/// A described format's volume from a file: the file's bytes are freed before the mesh is
/// built (peak memory).
fn load_described(path: &Path, read: ReadFn) -> Result<Loaded, Error> {
    let desc = read(&read_bytes_of(path)?, &path.display().to_string())?;
    Ok(build::volume(desc)?)
}

pub(crate) fn starts_after_space(bytes: &[u8], magic: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(0);
    bytes[start..].starts_with(magic)
}

/// The lower-case extension of a path.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Picks the format of a file: by content first, then by extension. `None` if neither
/// decides.
pub fn detect(bytes: &[u8], path: &Path) -> Option<&'static Format> {
    let head = &bytes[..bytes.len().min(4096)];
    FORMATS.iter().find(|f| (f.sniff)(head)).or_else(|| {
        let ext = extension(path)?;
        FORMATS
            .iter()
            .find(|f| f.extensions.contains(&ext.as_str()))
    })
}

/// The format a path's extension asks for when writing (HyperMesh for every other name).
pub fn format_for_writing(path: &Path) -> &'static Format {
    extension(path)
        .and_then(|ext| {
            FORMATS
                .iter()
                .find(|f| f.extensions.contains(&ext.as_str()))
        })
        .unwrap_or(&FORMATS[0])
}

fn unknown_format(name: &str) -> ParseError {
    let list: Vec<String> = FORMATS
        .iter()
        .map(|f| {
            let ext: Vec<String> = f.extensions.iter().map(|e| format!(".{e}")).collect();
            format!("{} ({})", f.name, ext.join(", "))
        })
        .collect();
    ParseError::new(
        name,
        1,
        format!(
            "unknown file format: the content is none that VoRANG reads; expected one of {}",
            list.join("; ")
        ),
    )
}

/// Reads a file held in memory into a description (the content decides the format). Errors
/// for HyperMesh files and for unknown formats.
pub fn read_description(bytes: &[u8], name: &str) -> Result<MeshDescription, ParseError> {
    match detect(bytes, Path::new(name)) {
        Some(Format {
            read: Some(read), ..
        }) => read(bytes, name),
        Some(f) if collection::Kind::of_format(f).is_some() => Err(ParseError::new(
            name,
            1,
            format!(
                "this is a {} file: read it as a collection (collection::Series)",
                f.name
            ),
        )),
        Some(_) => Err(ParseError::new(
            name,
            1,
            "this is a HyperMesh file; read it with the HyperMesh reader",
        )),
        None => Err(unknown_format(name)),
    }
}

fn read_bytes_of(path: &Path) -> Result<Vec<u8>, Error> {
    if path.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::other("is a directory, expected a mesh file"),
        ));
    }
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

/// The format to read `bytes` (a file's head, or a whole file held in memory) with: by content,
/// then by extension; text that neither decides goes to the HyperMesh reader, whose message
/// about the title line users of the thesis's format know; unknown binary content is an error
/// naming every format.
pub fn format_to_read(bytes: &[u8], path: &Path) -> Result<&'static Format, ParseError> {
    match detect(bytes, path) {
        Some(format) => Ok(format),
        None if looks_binary(bytes) => Err(unknown_format(&path.display().to_string())),
        None => Ok(&FORMATS[0]),
    }
}

/// The format of a file on disk ([`format_to_read`] on its first 4 KiB).
pub fn format_of_file(path: &Path) -> Result<&'static Format, Error> {
    Ok(format_to_read(&read_head(path), path)?)
}

impl Volume {
    /// Reads a mesh file of any supported format (HyperMesh, `.vtu`, `.vtk`, `.msh`, and of a
    /// collection — `.pvd`, `.pvtu`, `.vtm`, `.series` — or an Exodus II, XDMF or VTKHDF file
    /// its step 0; see [`crate::formats`]).
    /// Warnings (e.g. re-oriented cells) are returned, not printed.
    pub fn load(path: &Path) -> Result<(Volume, Vec<Warning>), Error> {
        load_volume(path)
    }
}

/// Loads a volume from any supported file (`volume FILE`); warnings are returned, not printed.
pub fn load_volume(path: &Path) -> Result<Loaded, Error> {
    (format_of_file(path)?.load)(path)
}

/// `data ?+? FILE`: `vol` with the fields of a file of any supported format.
pub fn load_data(vol: &Volume, path: &Path, append: bool) -> Result<Loaded, Error> {
    (format_of_file(path)?.load_data)(vol, path, append)
}

/// `vorang info FILE`: what a file of any supported format holds.
pub fn describe_file(path: &Path) -> Result<DescribedFile, Error> {
    (format_of_file(path)?.describe)(path)
}

/// The first 4 KiB of a file for detection (empty if it cannot be read: the reader that
/// follows reports why).
fn read_head(path: &Path) -> Vec<u8> {
    use std::io::Read;
    let mut head = Vec::with_capacity(4096);
    if let Ok(f) = std::fs::File::open(path) {
        let _ = f.take(4096).read_to_end(&mut head);
    }
    head
}

/// [`load_volume`] for a file held in memory (`name` labels messages and picks the format when
/// the content does not).
pub fn volume_from_bytes(bytes: &[u8], name: &str) -> Result<Loaded, ParseError> {
    (format_to_read(bytes, Path::new(name))?.load_bytes)(bytes, name)
}

fn looks_binary(bytes: &[u8]) -> bool {
    bytes[..bytes.len().min(512)]
        .iter()
        .any(|&b| b == 0 || (b < 0x20 && !b.is_ascii_whitespace() && b != 0x0c))
}

/// Whether a file is a HyperMesh file (or of unknown format and text, which the HyperMesh
/// reader then reports on).
pub fn is_hypermesh(bytes: &[u8], path: &Path) -> bool {
    format_to_read(bytes, path)
        .is_ok_and(|f| f.read.is_none() && collection::Kind::of_format(f).is_none())
}

/// Writes a volume in the format its file name asks for: `.vtu` (binary appended, zlib) or
/// HyperMesh (every other name, with `opts`). Returns warnings about what the format cannot
/// hold.
pub fn save_volume(
    vol: &Volume,
    path: &Path,
    opts: crate::formats::hypermesh::WriteOptions,
) -> Result<Vec<Warning>, Error> {
    let format = format_for_writing(path);
    match format.write {
        Some(write) => write(vol, path, opts),
        None => Err(Error::Invalid(format!(
            "{}: VoRANG cannot write {} files; write .vtu (VTK XML) or a HyperMesh file",
            path.display(),
            format.name
        ))),
    }
}

/// The 1-based line that byte `pos` of `bytes` is on.
pub fn line_of(bytes: &[u8], pos: usize) -> usize {
    1 + bytes[..pos.min(bytes.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_decides_before_the_extension() {
        let vtu = b"<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">";
        assert_eq!(
            detect(vtu, Path::new("a.msh")).unwrap().name,
            "VTK XML UnstructuredGrid"
        );
        assert_eq!(
            detect(b"# vtk DataFile Version 3.0\n", Path::new("a.vtu"))
                .unwrap()
                .name,
            "legacy VTK"
        );
        assert_eq!(
            detect(b"$MeshFormat\n4.1 0 8\n", Path::new("x"))
                .unwrap()
                .name,
            "Gmsh"
        );
        assert_eq!(
            detect(b"# HyperMesh 3D ASCII 0.7\n", Path::new("x.vtu"))
                .unwrap()
                .name,
            "HyperMesh"
        );
        assert_eq!(detect(b"junk", Path::new("x.msh")).unwrap().name, "Gmsh");
        assert!(detect(b"junk", Path::new("x.xyz")).is_none());
    }

    #[test]
    fn unknown_binary_content_is_a_clear_error() {
        let e = volume_from_bytes(b"\x00\x01\x02garbage", "thing.dat").unwrap_err();
        assert!(e.message.contains("unknown file format"), "{e}");
        assert!(e.message.contains(".vtu"), "{e}");
    }
}
