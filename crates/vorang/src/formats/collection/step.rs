//! Loading one step of a [`Series`]: its files read one at a time and merged
//! ([`super::merge`]), a `.pvtu` or `.vtm` among them expanded into its pieces, and the result
//! built into a volume — or, when the step has the same points and cells as the step loaded
//! before it, only its fields built on that step's mesh ([`crate::formats::build::fields_on`]):
//! the mesh with its adjacency and sort structures is shared, not built again
//! (docs/formats.md, "Time series and collections").

use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::merge::{Merge, PieceLabel};
use super::{FieldRanges, Kind, Series, pvtu, vtm};
use crate::data::ScalarType;
use crate::error::{Error, ParseError, Warning};
use crate::formats::build::{self, Shape};
use crate::formats::layout::LAYOUT_ARRAY;
use crate::formats::{Format, Loaded, MeshDescription, format_to_read};
use crate::volume::Volume;

/// How deep collections may list collections (a `.pvd` of `.vtm`s of `.pvtu`s is 2).
const MAX_NESTING: usize = 8;

/// A loaded step: its volume, and what the next step needs to share its mesh.
#[derive(Debug, Clone)]
pub struct StepVolume {
    /// The step's number (0-based).
    pub index: usize,
    pub volume: Arc<Volume>,
    reuse: Option<Reuse>,
}

/// What a step with the same points and cells builds its fields on.
#[derive(Debug, Clone)]
struct Reuse {
    shape: Arc<Shape>,
    /// A 128-bit digest of the cells (types, offsets, connectivity, polyhedra's faces); the
    /// points are compared exactly with the mesh's (whose points the polyhedra added follow).
    cells: u128,
}

impl StepVolume {
    /// Whether the mesh of `other` is this step's very mesh (shared, not rebuilt).
    pub fn shares_mesh(&self, other: &StepVolume) -> bool {
        Arc::ptr_eq(&self.volume.mesh, &other.volume.mesh)
    }

    /// Whether `desc` has this step's points and cells (and can be built on its shape).
    fn same_grid(&self, desc: &MeshDescription, cells: u128) -> Option<&Reuse> {
        let reuse = self.reuse.as_ref()?;
        let nodes = self.volume.mesh.nodes();
        let float = self.volume.coord_type == ScalarType::Float;
        let same = reuse.cells == cells
            && desc.float_coordinates == float
            && !desc.field_arrays.iter().any(|a| a.name == LAYOUT_ARRAY)
            && desc.nodes.len() + reuse.shape.added_points() == nodes.len()
            && desc
                .nodes
                .iter()
                .zip(nodes)
                .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits));
        same.then_some(reuse)
    }
}

/// The digest of a description's cells.
fn cells_digest(desc: &MeshDescription) -> u128 {
    let half = |seed: u64| {
        let mut h = std::hash::DefaultHasher::new();
        seed.hash(&mut h);
        desc.cells.types.hash(&mut h);
        desc.cells.offsets.hash(&mut h);
        desc.cells.connectivity.hash(&mut h);
        let faces = &desc.cells.faces;
        (&faces.cells, &faces.offsets, &faces.nodes).hash(&mut h);
        h.finish()
    };
    (u128::from(half(0x5eed_0001)) << 64) | u128::from(half(0x5eed_0002))
}

/// What a step's files gave: one description (merged from its pieces), or the volume of a
/// lone HyperMesh file (which no description can carry).
enum Input {
    Description(MeshDescription),
    Volume(Loaded),
}

impl Series {
    /// Loads step `index`. With `previous` (the step loaded before, usually the one shown): a
    /// step with the same points and cells shares its mesh and builds only its fields.
    pub fn load_step(
        &self,
        index: usize,
        previous: Option<&StepVolume>,
    ) -> Result<(StepVolume, Vec<Warning>), Error> {
        let step = self.steps.get(index).ok_or_else(|| {
            Error::Invalid(format!(
                "step {index} is out of range: {} has {}",
                self.source,
                self.range_text()
            ))
        })?;
        let mut warnings = Vec::new();
        let mut merge = Merge::new();
        let mut lone = None;
        for part in &step.parts {
            let label = PieceLabel {
                file: part.path.display().to_string(),
                from: self.source.clone(),
                line: part.line,
            };
            if let (Some(k), Kind::Steps(multi)) = (part.within, self.kind) {
                merge.add(multi.read_step(&part.path, k)?, label)?;
                continue;
            }
            let lone_part = step.parts.len() == 1;
            if let Some(input) =
                read_part(&part.path, &label, &mut merge, &mut warnings, lone_part, 0)?
            {
                lone = Some(input);
            }
        }
        let input = match lone {
            Some(input) => input,
            None => Input::Description(merge.finish().ok_or_else(|| {
                ParseError::new(
                    &self.source,
                    step.parts.first().map_or(1, |p| p.line),
                    format!(
                        "step {index} (t = {}) has no unstructured grid to show",
                        step.time
                    ),
                )
            })?),
        };
        let (volume, reuse, more) = match input {
            Input::Volume((vol, w)) => (Arc::new(vol), None, w),
            Input::Description(desc) => build_step(desc, previous)?,
        };
        warnings.extend(more);
        Ok((
            StepVolume {
                index,
                volume,
                reuse,
            },
            warnings,
        ))
    }

    /// Per field of the first step: its range (per component) over every step, each step
    /// loaded on the mesh of the one before it. `first` is a loaded step of this series.
    pub fn ranges(&self, first: &StepVolume) -> Result<FieldRanges, Error> {
        let n = first.volume.data.fields.len();
        let mut out: FieldRanges = (0..n).map(|i| first.volume.field_range(i)).collect();
        let mut previous = first.clone();
        for index in (0..self.steps.len()).filter(|&i| i != first.index) {
            let (step, _) = self.load_step(index, Some(&previous))?;
            for (i, range) in out.iter_mut().enumerate() {
                if let (Some(range), Some(more)) = (range, step.volume.field_range(i))
                    && more.len() == range.len()
                {
                    for (r, m) in range.iter_mut().zip(more) {
                        *r = (r.0.min(m.0), r.1.max(m.1));
                    }
                }
            }
            previous = step;
        }
        Ok(out)
    }
}

/// A step's volume, with what the next step needs to share its mesh.
type Built = (Arc<Volume>, Option<Reuse>, Vec<Warning>);

/// The volume of a step's description: on the previous step's mesh where the points and
/// cells are the same, built anew otherwise.
fn build_step(desc: MeshDescription, previous: Option<&StepVolume>) -> Result<Built, ParseError> {
    let cells = cells_digest(&desc);
    if let Some((prev, reuse)) = previous.and_then(|p| Some((p, p.same_grid(&desc, cells)?))) {
        let (vol, w) = build::fields_on(desc, &prev.volume, &reuse.shape)?;
        return Ok((Arc::new(vol), Some(reuse.clone()), w));
    }
    let (vol, shape, w) = build::volume_with_shape(desc)?;
    let reuse = shape.map(|shape| Reuse {
        shape: Arc::new(shape),
        cells,
    });
    Ok((Arc::new(vol), reuse, w))
}

/// A file named in a collection, relative to the collection's folder.
pub(super) fn resolve(collection: &Path, file: &str) -> PathBuf {
    collection.parent().unwrap_or(Path::new("")).join(file)
}

/// Reads one file of a step into `merge` (a `.pvtu` or `.vtm` piece by piece). A lone
/// HyperMesh file (`lone`: the step's only file) is loaded whole and returned.
fn read_part(
    path: &Path,
    label: &PieceLabel,
    merge: &mut Merge,
    warnings: &mut Vec<Warning>,
    lone: bool,
    depth: usize,
) -> Result<Option<Input>, Error> {
    let located = |msg: String| Error::from(ParseError::new(&label.from, label.line, msg));
    if depth > MAX_NESTING {
        return Err(located(format!(
            "{}: collections nested more than {MAX_NESTING} deep (does one list itself?)",
            label.file
        )));
    }
    if !path.is_file() {
        let why = if path.exists() {
            "is not a file"
        } else {
            "no such file"
        };
        return Err(located(format!("{}: {why}", label.file)));
    }
    let bytes = std::fs::read(path).map_err(|e| located(format!("{}: {e}", label.file)))?;
    let format: &Format = format_to_read(&bytes, path)?;
    match Kind::of_format(format) {
        Some(Kind::Pvtu) => {
            let pieces = pvtu::entries(&bytes, &label.file)?;
            drop(bytes);
            for p in pieces {
                let inner = PieceLabel {
                    file: resolve(path, &p.file).display().to_string(),
                    from: label.file.clone(),
                    line: p.line,
                };
                read_part(
                    &resolve(path, &p.file),
                    &inner,
                    merge,
                    warnings,
                    false,
                    depth + 1,
                )?;
            }
            Ok(None)
        }
        Some(Kind::Vtm) => {
            let leaves = vtm::leaves(&bytes, &label.file)?;
            drop(bytes);
            read_blocks(path, &label.file, leaves, merge, warnings, depth)
        }
        Some(kind @ (Kind::Pvd | Kind::SeriesJson)) => Err(located(format!(
            "{}: a {} is a time series; it cannot be one part of a step",
            label.file,
            kind.noun()
        ))),
        // A file that holds steps itself, listed as one part: its step 0.
        Some(Kind::Steps(_)) | None => match format.read {
            Some(read) => {
                let desc = read(&bytes, &label.file)?;
                drop(bytes);
                merge.add(desc, label.clone())?;
                Ok(None)
            }
            None if lone && depth == 0 => {
                drop(bytes);
                Ok(Some(Input::Volume((format.load)(path)?)))
            }
            None => Err(located(format!(
                "{}: a {} file cannot be merged with other pieces; write the pieces as .vtu",
                label.file, format.name
            ))),
        },
    }
}

/// The blocks of a `.vtm`: unstructured grids (and collections of them) merged, other block
/// types skipped with a warning.
fn read_blocks(
    path: &Path,
    shown: &str,
    leaves: Vec<vtm::Leaf>,
    merge: &mut Merge,
    warnings: &mut Vec<Warning>,
    depth: usize,
) -> Result<Option<Input>, Error> {
    for leaf in leaves {
        let file = resolve(path, &leaf.entry.file);
        let inner = PieceLabel {
            file: file.display().to_string(),
            from: shown.to_string(),
            line: leaf.entry.line,
        };
        let head = read_head(&file);
        if let Some(ty) = super::xml::vtk_type(&head)
            && !matches!(
                ty.as_str(),
                "UnstructuredGrid" | "PUnstructuredGrid" | "vtkMultiBlockDataSet"
            )
        {
            let block = leaf
                .name
                .map(|n| format!("block \"{n}\""))
                .unwrap_or_else(|| "a block".into());
            warnings.push(Warning {
                file: shown.to_string(),
                line: Some(leaf.entry.line),
                message: format!(
                    "{block} is a {ty}, not an unstructured grid: skipped ({})",
                    inner.file
                ),
            });
            continue;
        }
        read_part(&file, &inner, merge, warnings, false, depth + 1)?;
    }
    Ok(None)
}

/// The first 4 KiB of a file (empty where it cannot be read: reading it reports why).
fn read_head(path: &Path) -> Vec<u8> {
    use std::io::Read;
    let mut head = Vec::with_capacity(4096);
    if let Ok(f) = std::fs::File::open(path) {
        let _ = f.take(4096).read_to_end(&mut head);
    }
    head
}
