//! VTKHDF `UnstructuredGrid` files (`.vtkhdf`, `.hdf`): VTK's HDF5 layout, with its time
//! steps (`/VTKHDF/Steps`) — docs/formats.md, "VTKHDF".
//!
//! Everything sits under the group `/VTKHDF`: `Points`, `Types`, `Connectivity`, `Offsets`,
//! per partition the counts `NumberOfPoints`, `NumberOfCells`, `NumberOfConnectivityIds`, and
//! the arrays in `PointData/` and `CellData/`. A file is written in parts (partitions), each with
//! its own 0-based connectivity and one offset more than it has cells; the parts of a step are
//! joined here into one grid. With `Steps`, each step says where its parts, points, cells and
//! connectivity start (`PartOffsets`, `PointOffsets`, `CellOffsets`, `ConnectivityIdOffsets`)
//! and where each array's values start (`PointDataOffsets/NAME`, `CellDataOffsets/NAME`): a
//! solver writes the grid once and only the arrays per step, so steps that share the grid share
//! the offsets (and VoRANG then shares the mesh, docs/formats.md, "Time series").

use std::path::Path;

use super::hdf::{self, H5};
use super::{Array, ArrayValues, Cells, FileStep, MeshDescription};
use crate::error::ParseError;

const ROOT: &str = "/VTKHDF";

/// Whether a file's head is a VTKHDF file: HDF5 with the group `VTKHDF` named near its start
/// (where a small file's root group lists it).
pub fn sniff(head: &[u8]) -> bool {
    hdf::is_hdf5(head) && head.windows(6).any(|w| w == b"VTKHDF")
}

/// The partitions of step 0 of a file held in memory.
pub fn read_parts(bytes: &[u8], name: &str) -> Result<Vec<MeshDescription>, ParseError> {
    describe(&H5::from_bytes(bytes, name)?, 0)
}

/// The steps of a file: `Steps/Values` are their times (the step numbers where a file has
/// none); a file without `Steps` is one step at time 0.
pub fn steps(path: &Path, name: &str) -> Result<Vec<FileStep>, ParseError> {
    let h5 = H5::open(path, name)?;
    check_type(&h5)?;
    let n = step_count(&h5)?;
    let values = format!("{ROOT}/Steps/Values");
    let times = if n > 0 && h5.has(&values) {
        let t = h5.read(&values)?;
        if t.len() < n {
            return Err(located(
                &h5,
                &values,
                format!("{} times for {n} steps", t.len()),
            ));
        }
        (0..n).map(|i| t.get(i)).collect()
    } else {
        (0..n.max(1)).map(|i| i as f64).collect::<Vec<_>>()
    };
    Ok(times
        .into_iter()
        .enumerate()
        .map(|(index, time)| FileStep {
            time: if n == 0 { 0.0 } else { time },
            file: path.to_path_buf(),
            index,
        })
        .collect())
}

/// The partitions of step `index` of the file at `path`.
pub fn read_step(
    path: &Path,
    name: &str,
    index: usize,
) -> Result<Vec<MeshDescription>, ParseError> {
    describe(&H5::open(path, name)?, index)
}

fn located(h5: &H5, what: &str, message: impl std::fmt::Display) -> ParseError {
    ParseError::new(&h5.name, 0, format!("{what}: {message}"))
}

/// `/VTKHDF` says it holds an unstructured grid.
fn check_type(h5: &H5) -> Result<(), ParseError> {
    if !h5.has(ROOT) {
        return Err(located(
            h5,
            "group /VTKHDF",
            "not in the file: not a VTKHDF file",
        ));
    }
    match h5.attr_text(ROOT, "Type") {
        Some(t) if t == "UnstructuredGrid" => Ok(()),
        Some(t) => Err(located(
            h5,
            "group /VTKHDF",
            format!("Type is \"{t}\"; VoRANG reads VTKHDF UnstructuredGrid files"),
        )),
        None => Err(located(h5, "group /VTKHDF", "has no attribute Type")),
    }
}

/// The number of steps (`Steps` attribute `NSteps`), 0 without `Steps`.
fn step_count(h5: &H5) -> Result<usize, ParseError> {
    let steps = format!("{ROOT}/Steps");
    if !h5.has(&steps) {
        return Ok(0);
    }
    let n = h5
        .attr_numbers(&steps, "NSteps")
        .and_then(|v| v.first().copied())
        .ok_or_else(|| located(h5, "group /VTKHDF/Steps", "has no attribute NSteps"))?;
    if !(n >= 0.0 && n.fract() == 0.0 && n < 1e9) {
        return Err(located(h5, "group /VTKHDF/Steps", format!("NSteps = {n}")));
    }
    Ok(n as usize)
}

/// Where one step's data start in the file's datasets.
#[derive(Default)]
struct Start {
    part: usize,
    parts: usize,
    point: u64,
    cell: u64,
    connectivity: u64,
}

/// Entry `index` of a per-step dataset (`Steps/NAME`), `None` if it is absent.
fn per_step(h5: &H5, name: &str, index: usize) -> Result<Option<u64>, ParseError> {
    let path = format!("{ROOT}/Steps/{name}");
    if !h5.has(&path) {
        return Ok(None);
    }
    let v = h5.read_int_rows(&path, Some((index as u64, 1)))?;
    match v.first() {
        Some(&x) if x >= 0 => Ok(Some(x as u64)),
        other => Err(located(
            h5,
            &format!("dataset {path}"),
            format!("step {index}: {other:?} is not a count"),
        )),
    }
}

fn start_of(h5: &H5, index: usize, parts_in_file: usize) -> Result<Start, ParseError> {
    let n = step_count(h5)?;
    if n == 0 {
        if index > 0 {
            return Err(located(h5, "group /VTKHDF", format!("has no step {index}")));
        }
        return Ok(Start {
            parts: parts_in_file,
            ..Start::default()
        });
    }
    if index >= n {
        return Err(located(
            h5,
            "group /VTKHDF/Steps",
            format!("has {n} steps, not step {index}"),
        ));
    }
    let get = |name| per_step(h5, name, index).map(|v| v.unwrap_or(0));
    Ok(Start {
        part: get("PartOffsets")? as usize,
        parts: per_step(h5, "NumberOfParts", index)?.map_or(parts_in_file, |p| p as usize),
        point: get("PointOffsets")?,
        cell: get("CellOffsets")?,
        connectivity: get("ConnectivityIdOffsets")?,
    })
}

/// The partitions of step `index`, each a description of its own (the caller merges them:
/// the points a writer repeats on the faces between partitions become one again, and ghost
/// cells are dropped).
fn describe(h5: &H5, index: usize) -> Result<Vec<MeshDescription>, ParseError> {
    check_type(h5)?;
    let counts =
        |name: &str| -> Result<Vec<i64>, ParseError> { h5.read_ints(&format!("{ROOT}/{name}")) };
    let n_points = counts("NumberOfPoints")?;
    let n_cells = counts("NumberOfCells")?;
    let n_ids = counts("NumberOfConnectivityIds")?;
    let start = start_of(h5, index, n_points.len())?;
    let count_of = |v: &[i64], what: &str, p: usize| -> Result<u64, ParseError> {
        match v.get(p) {
            Some(&c) if c >= 0 => Ok(c as u64),
            _ => Err(located(
                h5,
                &format!("dataset /VTKHDF/{what}"),
                format!("has no count for part {p} (step {index})"),
            )),
        }
    };
    let point_offsets = array_offsets(h5, "PointData", "PointDataOffsets", index, start.point)?;
    let cell_offsets = array_offsets(h5, "CellData", "CellDataOffsets", index, start.cell)?;
    let (mut point, mut cell, mut conn) = (0u64, 0u64, start.connectivity);
    let last = start.part.saturating_add(start.parts);
    if last > n_points.len() || last > n_cells.len() || last > n_ids.len() {
        return Err(located(
            h5,
            "dataset /VTKHDF/NumberOfPoints",
            format!(
                "step {index} has partitions {} … {}, the counts list {}",
                start.part,
                last.saturating_sub(1),
                n_points.len().min(n_cells.len()).min(n_ids.len())
            ),
        ));
    }
    let mut parts = Vec::new();
    for p in start.part..last {
        let np = count_of(&n_points, "NumberOfPoints", p)?;
        let nc = count_of(&n_cells, "NumberOfCells", p)?;
        let ni = count_of(&n_ids, "NumberOfConnectivityIds", p)?;
        let mut desc = MeshDescription {
            source: h5.name.clone(),
            format: "VTKHDF UnstructuredGrid".into(),
            ..MeshDescription::default()
        };
        let pts = h5.read_rows(&format!("{ROOT}/Points"), Some((start.point + point, np)))?;
        if pts.len() as u64 != np * 3 {
            return Err(located(
                h5,
                "dataset /VTKHDF/Points",
                "expected 3 coordinates a point",
            ));
        }
        desc.nodes = (0..np as usize)
            .map(|i| [pts.get(3 * i), pts.get(3 * i + 1), pts.get(3 * i + 2)])
            .collect();
        desc.float_coordinates = matches!(pts, ArrayValues::F32(_)) && np > 0;
        drop(pts);
        let part = Part {
            first_cell: start.cell + cell,
            // Each part written before this one added one offset more than it has cells.
            first_offset: start.cell + cell + p as u64,
            cells: nc,
            first_id: conn,
            ids: ni,
            points: np,
        };
        add_cells(h5, &mut desc.cells, &part)?;
        desc.point_arrays = arrays(h5, "PointData", &point_offsets, point, np)?;
        desc.cell_arrays = arrays(h5, "CellData", &cell_offsets, cell, nc)?;
        parts.push(desc);
        point += np;
        cell += nc;
        conn += ni;
    }
    Ok(parts)
}

/// Where one part's cells are in the datasets: its rows of `Types` and `Offsets`, of
/// `Connectivity`, and its number of points.
struct Part {
    first_cell: u64,
    first_offset: u64,
    cells: u64,
    first_id: u64,
    ids: u64,
    points: u64,
}

/// Cells read per batch: the types, offsets and node numbers of a large grid are read a batch
/// at a time, so that they never exist whole beside the cells (as 64-bit numbers they would
/// be twice their size; docs/formats.md, "Speed and memory").
const BATCH: u64 = 1 << 18;

/// One part's cells (0-based connectivity within the part), batch by batch.
fn add_cells(h5: &H5, cells: &mut Cells, part: &Part) -> Result<(), ParseError> {
    add_cells_by(h5, cells, part, BATCH)
}

/// [`add_cells`] `batch` cells at a time.
fn add_cells_by(h5: &H5, cells: &mut Cells, part: &Part, batch: u64) -> Result<(), ParseError> {
    let rows = |name: &str, first: u64, n: u64| {
        h5.read_int_rows(&format!("{ROOT}/{name}"), Some((first, n)))
    };
    // Reserved for the counts only where the datasets hold that many rows: a corrupt count
    // reserves nothing (the reads then say what is missing).
    let holds = |name: &str, end: u64| {
        h5.shape(&format!("{ROOT}/{name}"))
            .is_ok_and(|s| s.first().is_some_and(|&rows| end <= rows))
    };
    if holds("Types", part.first_cell.saturating_add(part.cells))
        && holds("Connectivity", part.first_id.saturating_add(part.ids))
    {
        let (n, ids) = (part.cells as usize, part.ids as usize);
        cells.types.reserve_exact(n);
        cells.offsets.reserve_exact(n + 1);
        cells.connectivity.reserve_exact(ids);
    }
    let mut nodes = Vec::new();
    let mut first = 0;
    while first < part.cells {
        let count = batch.min(part.cells - first);
        let types = rows("Types", part.first_cell + first, count)?;
        let offsets = rows("Offsets", part.first_offset + first, count + 1)?;
        let (lo, hi) = (offsets[0], offsets[offsets.len() - 1]);
        if lo < 0 || hi < lo || hi as u64 > part.ids {
            return Err(located(
                h5,
                "dataset /VTKHDF/Offsets",
                format!(
                    "cells {} … {}: offsets {lo} … {hi} outside the connectivity's {} ids",
                    first,
                    first + count - 1,
                    part.ids
                ),
            ));
        }
        let ids = rows("Connectivity", part.first_id + lo as u64, (hi - lo) as u64)?;
        for (k, &ty) in types.iter().enumerate() {
            let i = first as usize + k;
            let (a, b) = (offsets[k], offsets[k + 1]);
            if a < lo || b < a || b > hi {
                return Err(located(
                    h5,
                    "dataset /VTKHDF/Offsets",
                    format!(
                        "cell {i}: offsets {a} … {b} outside the connectivity's {} ids",
                        part.ids
                    ),
                ));
            }
            nodes.clear();
            for &id in &ids[(a - lo) as usize..(b - lo) as usize] {
                if id < 0 || id as u64 >= part.points {
                    return Err(located(
                        h5,
                        "dataset /VTKHDF/Connectivity",
                        format!(
                            "cell {i}: point {id} is not one of the part's {} points",
                            part.points
                        ),
                    ));
                }
                nodes.push(id as u64);
            }
            let ty = u8::try_from(ty).map_err(|_| {
                located(h5, "dataset /VTKHDF/Types", format!("cell {i}: type {ty}"))
            })?;
            cells.push(ty, &nodes);
        }
        first += count;
    }
    Ok(())
}

/// The arrays of `group` (`PointData` or `CellData`, by name) with the row where the step's
/// values start: `Steps/OFFSETS/NAME`, or `first` (the step's first point or cell) without it.
fn array_offsets(
    h5: &H5,
    group: &str,
    offsets: &str,
    index: usize,
    first: u64,
) -> Result<Vec<(String, u64)>, ParseError> {
    let path = format!("{ROOT}/{group}");
    if !h5.has(&path) {
        return Ok(Vec::new());
    }
    let (_, mut names) = h5.members(&path)?;
    names.sort();
    names
        .into_iter()
        .map(|name| {
            let from = per_step(h5, &format!("{offsets}/{name}"), index)?.unwrap_or(first);
            Ok((name, from))
        })
        .collect()
}

/// One part's arrays: `count` rows from `skip` rows after the step's start of each.
fn arrays(
    h5: &H5,
    group: &str,
    starts: &[(String, u64)],
    skip: u64,
    count: u64,
) -> Result<Vec<Array>, ParseError> {
    let mut out = Vec::new();
    for (name, from) in starts {
        let data = format!("{ROOT}/{group}/{name}");
        let shape = h5.shape(&data)?;
        let components = shape.iter().skip(1).product::<u64>().max(1) as usize;
        let values = h5.read_rows(&data, Some((from + skip, count)))?;
        out.push(Array {
            name: name.clone(),
            components,
            values,
            line: 0,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffing_needs_the_hdf5_magic_and_the_group_name() {
        let mut head = hdf::MAGIC.to_vec();
        head.extend_from_slice(b"\0\0....VTKHDF..");
        assert!(sniff(&head));
        assert!(!sniff(b"VTKHDF"));
        assert!(!sniff(hdf::MAGIC));
    }

    #[test]
    fn bad_bytes_are_an_error_naming_the_file() {
        let e = read_parts(b"\x89HDF\r\n\x1a\nnonsense", "x.vtkhdf").unwrap_err();
        assert!(e.to_string().starts_with("x.vtkhdf: "), "{e}");
    }

    /// Batches of any size give the cells read in one batch (a batch boundary inside a cell's
    /// node numbers is where an off-by-one would show), and a part's offsets pointing past its
    /// connectivity are an error naming the dataset.
    #[test]
    fn cells_read_in_batches_are_the_cells_read_at_once() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../tests/data/multistep/flow.vtkhdf");
        let h5 = H5::open(&path, "flow.vtkhdf").unwrap();
        let count = |name: &str| h5.read_ints(&format!("{ROOT}/{name}")).unwrap()[0] as u64;
        let part = Part {
            first_cell: 0,
            first_offset: 0,
            cells: count("NumberOfCells"),
            first_id: 0,
            ids: count("NumberOfConnectivityIds"),
            points: count("NumberOfPoints"),
        };
        assert!(part.cells > 10);
        let mut whole = Cells::default();
        add_cells(&h5, &mut whole, &part).unwrap();
        assert_eq!(whole.len() as u64, part.cells);
        for batch in [1, 2, 3, 7, part.cells - 1] {
            let mut cells = Cells::default();
            add_cells_by(&h5, &mut cells, &part, batch).unwrap();
            assert_eq!(cells.types, whole.types, "batch {batch}");
            assert_eq!(cells.offsets, whole.offsets, "batch {batch}");
            assert_eq!(cells.connectivity, whole.connectivity, "batch {batch}");
        }
        let short = Part {
            ids: part.ids - 1,
            ..part
        };
        let e = add_cells_by(&h5, &mut Cells::default(), &short, 3).unwrap_err();
        assert!(e.to_string().contains("/VTKHDF/Offsets"), "{e}");
    }
}
