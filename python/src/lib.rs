//! The `vorang._vorang` extension module: numpy arrays in, numpy images out, over the core
//! library. The pure-Python package `vorang` (python/vorang/__init__.py) re-exports it and adds
//! the map helpers.
//!
//! This file holds `Volume` and the image functions; `render` and `animate` (`render`) set a
//! scene from their keywords (`scene`) on a volume or a step of a `Series` (`series`).

mod render;
mod scene;
mod series;

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{IntoPyArray, PyReadonlyArrayDyn};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use vorang::formats::{self, Array, ArrayValues, Cells, MeshDescription, cell_type};
use vorang::framebuffer::{Framebuffer, write_image};
use vorang::{Error, ParseError};

/// The core's error as a Python exception: files → `OSError`, everything else → `ValueError`.
fn py_err(e: Error) -> PyErr {
    match e {
        Error::Io { .. } => PyOSError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// A tetrahedral mesh with its fields (the core's `Volume`).
#[pyclass(name = "Volume", module = "vorang", frozen)]
pub(crate) struct PyVolume {
    pub(crate) inner: Arc<vorang::Volume>,
}

/// `numpy.asarray(obj)` with its dtype kind ('f', 'i', 'u', 'b', …) and shape.
fn as_array<'py>(
    py: Python<'py>,
    obj: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<(Bound<'py, PyAny>, char, Vec<usize>)> {
    let np = py.import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj,))
        .map_err(|e| PyValueError::new_err(format!("{what}: not an array ({e})")))?;
    let kind: String = arr.getattr("dtype")?.getattr("kind")?.extract()?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    Ok((arr, kind.chars().next().unwrap_or('?'), shape))
}

/// A shape as Python writes it: (4,), (4, 2).
fn shape_str(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

fn dtype_name(arr: &Bound<'_, PyAny>) -> String {
    arr.getattr("dtype")
        .and_then(|d| d.str())
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "?".into())
}

/// The values of an array in logical (C) order, whatever its strides, as f64.
fn f64_values(arr: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    let conv = arr.call_method1("astype", ("float64",))?;
    let ro: PyReadonlyArrayDyn<f64> = conv.extract()?;
    Ok(ro.as_array().iter().copied().collect())
}

fn f32_values(arr: &Bound<'_, PyAny>) -> PyResult<Vec<f32>> {
    let conv = arr.call_method1("astype", ("float32",))?;
    let ro: PyReadonlyArrayDyn<f32> = conv.extract()?;
    Ok(ro.as_array().iter().copied().collect())
}

fn i64_values(arr: &Bound<'_, PyAny>) -> PyResult<Vec<i64>> {
    let conv = arr.call_method1("astype", ("int64",))?;
    let ro: PyReadonlyArrayDyn<i64> = conv.extract()?;
    Ok(ro.as_array().iter().copied().collect())
}

/// One data dict's arrays, checked for shape and type.
fn data_arrays(
    py: Python<'_>,
    data: Option<&Bound<'_, PyDict>>,
    count: usize,
    kind: &str,
) -> PyResult<Vec<Array>> {
    let mut out = Vec::new();
    let Some(data) = data else {
        return Ok(out);
    };
    for (key, value) in data.iter() {
        let name: String = key.extract().map_err(|_| {
            PyValueError::new_err(format!("{kind}_data: names must be strings, found {key}"))
        })?;
        let what = format!("{kind}_data[{name:?}]");
        let (arr, k, shape) = as_array(py, &value, &what)?;
        let components = match shape.as_slice() {
            [n] if *n == count => 1,
            [n, c] if *n == count && *c >= 1 => *c,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{what}: expected shape ({count},) or ({count}, k) — one row per {} — found {}",
                    if kind == "point" {
                        "point"
                    } else {
                        "tetrahedron"
                    },
                    shape_str(&shape)
                )));
            }
        };
        let values = match k {
            'f' if dtype_name(&arr) == "float32" => ArrayValues::F32(f32_values(&arr)?),
            'f' => ArrayValues::F64(f64_values(&arr)?),
            'i' | 'u' | 'b' => ArrayValues::Int(i64_values(&arr)?),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{what}: expected numbers (float or int), found dtype {}",
                    dtype_name(&arr)
                )));
            }
        };
        out.push(Array {
            name,
            components,
            values,
            line: 1,
        });
    }
    Ok(out)
}

/// A message of the core about arrays, without the "file:line:" of file input.
fn array_err(e: ParseError) -> PyErr {
    PyValueError::new_err(e.message)
}

/// Points as (N, 3) coordinates, and whether they came as float32.
fn read_points(py: Python<'_>, points: &Bound<'_, PyAny>) -> PyResult<(Vec<[f64; 3]>, bool)> {
    let (parr, pk, pshape) = as_array(py, points, "points")?;
    if pshape.len() != 2 || pshape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "points: expected shape (N, 3), found {}",
            shape_str(&pshape)
        )));
    }
    if !matches!(pk, 'f' | 'i' | 'u') {
        return Err(PyValueError::new_err(format!(
            "points: expected floats, found dtype {}",
            dtype_name(&parr)
        )));
    }
    let float32 = dtype_name(&parr) == "float32";
    let flat = f64_values(&parr)?;
    let nodes: Vec<[f64; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();

    Ok((nodes, float32))
}

/// Refuses negative indices (the core checks the upper bound with its own message).
fn check_indices(idx: &[i64], per: usize, n_nodes: usize, what: &str) -> PyResult<()> {
    if let Some(p) = idx.iter().position(|&i| i < 0) {
        return Err(PyValueError::new_err(format!(
            "{what}[{}, {}] = {} is negative: point indices are 0-based, 0 … {}",
            p / per,
            p % per,
            idx[p],
            n_nodes.saturating_sub(1)
        )));
    }
    Ok(())
}

/// The volume of a description built from arrays.
fn build(
    py: Python<'_>,
    nodes: Vec<[f64; 3]>,
    float32: bool,
    cells: Cells,
    point_data: Option<&Bound<'_, PyDict>>,
    cell_data: Option<&Bound<'_, PyDict>>,
) -> PyResult<PyVolume> {
    let point_arrays = data_arrays(py, point_data, nodes.len(), "point")?;
    let cell_arrays = data_arrays(py, cell_data, cells.len(), "cell")?;
    let desc = MeshDescription {
        source: "<arrays>".into(),
        format: "numpy arrays".into(),
        nodes,
        float_coordinates: float32,
        cells,
        point_arrays,
        cell_arrays,
        field_arrays: Vec::new(),
        points_line: 1,
        cells_line: 1,
        warnings: Vec::new(),
    };
    let (vol, warnings) = formats::build::volume(desc).map_err(array_err)?;
    // Arrays have no file and line to name: the message alone.
    warn_all(py, warnings.iter().map(|w| w.message.clone()))?;
    Ok(PyVolume {
        inner: Arc::new(vol),
    })
}

#[pymethods]
impl PyVolume {
    /// Volume(points, tets, point_data=None, cell_data=None)
    ///
    /// points: (N, 3) float array; tets: (M, 4) int array of 0-based point indices;
    /// point_data / cell_data: dicts name → (N,) / (N, k) or (M,) / (M, k) arrays. Fields are
    /// numbered point data first, then cell data, in dict order; their names can be used in
    /// map files (`DataField "name"`). Integer cell arrays with values in 0..255 become byte
    /// Constant fields (materials); 3-component arrays become float[3] vector fields. Raises ValueError for wrong shapes, indices out of range,
    /// non-finite coordinates and degenerate tetrahedra.
    #[new]
    #[pyo3(signature = (points, tets, point_data=None, cell_data=None))]
    fn new(
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        tets: &Bound<'_, PyAny>,
        point_data: Option<&Bound<'_, PyDict>>,
        cell_data: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let (nodes, float32) = read_points(py, points)?;
        let (tarr, tk, tshape) = as_array(py, tets, "tets")?;
        if tshape.len() != 2 || tshape[1] != 4 {
            return Err(PyValueError::new_err(format!(
                "tets: expected shape (M, 4), found {}",
                shape_str(&tshape)
            )));
        }
        if !matches!(tk, 'i' | 'u') {
            return Err(PyValueError::new_err(format!(
                "tets: expected integers (0-based point indices), found dtype {}",
                dtype_name(&tarr)
            )));
        }
        let idx = i64_values(&tarr)?;
        check_indices(&idx, 4, nodes.len(), "tets")?;
        let mut cells = Cells::default();
        for c in idx.chunks_exact(4) {
            let n: Vec<u64> = c.iter().map(|&i| i as u64).collect();
            cells.push(cell_type::TETRA, &n);
        }
        build(py, nodes, float32, cells, point_data, cell_data)
    }

    /// Volume._from_blocks(points, blocks, point_data=None, cell_data=None): blocks is a list
    /// of (VTK cell type, (k, n) int array); non-tetrahedral volume cells (hexahedra, voxels,
    /// wedges, pyramids, quadratic and Lagrange cells, polyhedra) are split as the file readers
    /// split them, other cells are skipped with a warning. A polyhedron's row (type 42) is its
    /// face stream: the number of faces, then each face as its number of points and its
    /// points. Cell data covers the cells of all blocks in order. (Used by from_meshio /
    /// from_pyvista.)
    #[staticmethod]
    #[pyo3(signature = (points, blocks, point_data=None, cell_data=None))]
    fn _from_blocks(
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        blocks: Vec<(u8, Bound<'_, PyAny>)>,
        point_data: Option<&Bound<'_, PyDict>>,
        cell_data: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let (nodes, float32) = read_points(py, points)?;
        let mut cells = Cells::default();
        for (ty, conn) in blocks {
            let (arr, k, shape) = as_array(py, &conn, "cells")?;
            if shape.len() != 2 || !matches!(k, 'i' | 'u') {
                return Err(PyValueError::new_err(format!(
                    "cells of type {}: expected an (k, n) integer array, found shape {} of dtype {}",
                    cell_type::name(ty),
                    shape_str(&shape),
                    dtype_name(&arr)
                )));
            }
            let idx = i64_values(&arr)?;
            check_indices(&idx, shape[1].max(1), nodes.len(), "cells")?;
            for c in idx.chunks_exact(shape[1].max(1)) {
                if ty == cell_type::POLYHEDRON {
                    // A polyhedron's row is its face stream.
                    cells.push_face_stream(c).map_err(|m| {
                        PyValueError::new_err(format!(
                            "cells: the face stream of cell {} (a polyhedron): {m}",
                            cells.len() + 1
                        ))
                    })?;
                    continue;
                }
                let n: Vec<u64> = c.iter().map(|&i| i as u64).collect();
                cells.push(ty, &n);
            }
        }
        build(py, nodes, float32, cells, point_data, cell_data)
    }
    /// Volume.read(path): reads a mesh file of any format VoRANG reads (HyperMesh, .vtu,
    /// .vtk, .msh, Exodus II, XDMF, VTKHDF; of a collection — .pvd, .pvtu, .vtm, .series —
    /// or a file with time steps, step 0: vorang.Series.read gives them all). OSError for
    /// files that cannot be read, ValueError for invalid content.
    #[staticmethod]
    fn read(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        if !path.exists() {
            return Err(PyOSError::new_err(format!(
                "{}: no such file",
                path.display()
            )));
        }
        let (vol, warnings) = py.detach(|| vorang::Volume::load(&path)).map_err(py_err)?;
        warn_all(py, warnings.iter().map(|w| w.to_string()))?;
        Ok(PyVolume {
            inner: Arc::new(vol),
        })
    }

    /// Volume.from_meshio(mesh): a Volume from a meshio.Mesh (duck-typed, no meshio needed
    /// here): points, cells, point_data, cell_data. Hexahedra, wedges, pyramids, Lagrange cells
    /// (VTK_LAGRANGE_*) and polyhedra ("polyhedronN") are split into tetrahedra as the file
    /// readers split them; surface and line cells are skipped.
    #[staticmethod]
    fn from_meshio<'py>(py: Python<'py>, mesh: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        py.import("vorang")?.getattr("_from_meshio")?.call1((mesh,))
    }

    /// Volume.from_pyvista(grid): a Volume from a PyVista UnstructuredGrid (duck-typed):
    /// points, celltypes, cells, point_data, cell_data; mixed, voxel, Lagrange cells (as
    /// `pyvista.UnstructuredGrid(*dolfinx.plot.vtk_mesh(V))` has them) and polyhedra (through
    /// the grid's face stream) split as the readers do.
    #[staticmethod]
    fn from_pyvista<'py>(py: Python<'py>, grid: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        py.import("vorang")?
            .getattr("_from_pyvista")?
            .call1((grid,))
    }

    /// field_range(field) -> (lo, hi): the range of a scalar field (a name or a number) over
    /// the mesh, as `vorang info` prints it; ValueError for vector fields and unknown names.
    fn field_range(&self, field: &Bound<'_, PyAny>) -> PyResult<(f64, f64)> {
        let vol = &self.inner;
        let i = field_number(vol, field)?;
        match vol.field_range(i).as_deref() {
            Some([(lo, hi)]) => Ok((*lo, *hi)),
            Some(r) => Err(PyValueError::new_err(format!(
                "field {i} has {} components: give a scalar field",
                r.len()
            ))),
            None => Err(PyValueError::new_err(format!(
                "no field {i} ({} fields)",
                vol.data.fields.len()
            ))),
        }
    }

    /// Number of points.
    #[getter]
    fn n_points(&self) -> usize {
        self.inner.mesh.node_count()
    }

    /// Number of tetrahedra.
    #[getter]
    fn n_tets(&self) -> usize {
        self.inner.mesh.tet_count()
    }

    /// The field names in field-number order (None for unnamed fields).
    #[getter]
    fn field_names(&self) -> Vec<Option<String>> {
        self.inner
            .data
            .fields
            .iter()
            .map(|f| f.name.clone())
            .collect()
    }

    /// Points as an (N, 3) float64 array.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let flat: Vec<f64> = self.inner.mesh.nodes().iter().flatten().copied().collect();
        let n = flat.len() / 3;
        numpy::ndarray::Array2::from_shape_vec((n, 3), flat)
            .expect("shape")
            .into_pyarray(py)
            .into_any()
    }

    /// Tetrahedra as an (M, 4) int64 array (0-based, as oriented by VoRANG).
    #[getter]
    fn tets<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let flat: Vec<i64> = self
            .inner
            .mesh
            .tets()
            .iter()
            .flatten()
            .map(|&i| i64::from(i))
            .collect();
        let n = flat.len() / 4;
        numpy::ndarray::Array2::from_shape_vec((n, 4), flat)
            .expect("shape")
            .into_pyarray(py)
            .into_any()
    }

    fn __repr__(&self) -> String {
        format!(
            "vorang.Volume({} points, {} tetrahedra, {} fields)",
            self.inner.mesh.node_count(),
            self.inner.mesh.tet_count(),
            self.inner.data.fields.len()
        )
    }
}

/// The number of the field `field` names: a number, or a name (ValueError naming the fields
/// for an unknown one).
fn field_number(vol: &vorang::Volume, field: &Bound<'_, PyAny>) -> PyResult<usize> {
    if let Ok(i) = field.extract::<usize>() {
        return Ok(i);
    }
    let name: String = field.extract()?;
    vol.data
        .fields
        .iter()
        .position(|f| f.name.as_deref() == Some(name.as_str()))
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "no field named {name:?}; the fields are {:?}",
                vol.data
                    .fields
                    .iter()
                    .map(|f| f.name.clone().unwrap_or_default())
                    .collect::<Vec<_>>()
            ))
        })
}

fn warn_all(py: Python<'_>, msgs: impl Iterator<Item = String>) -> PyResult<()> {
    let warnings = py.import("warnings")?;
    for m in msgs {
        warnings.call_method1("warn", (m,))?;
    }
    Ok(())
}

/// An (h, w, 4) or (h, w, 3) float array as a framebuffer (`transparent`: straight alpha, as
/// after `background none`).
fn framebuffer_of(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    transparent: bool,
) -> PyResult<Framebuffer> {
    let (arr, k, shape) = as_array(py, image, "image")?;
    if shape.len() != 3 || !(shape[2] == 4 || shape[2] == 3) || !matches!(k, 'f' | 'i' | 'u') {
        return Err(PyValueError::new_err(format!(
            "image: expected a float array of shape (h, w, 4) or (h, w, 3), found shape {} of dtype {}",
            shape_str(&shape),
            dtype_name(&arr)
        )));
    }
    let (h, w, c) = (shape[0], shape[1], shape[2]);
    vorang::render::check_size(w, h).map_err(PyValueError::new_err)?;
    let values = f32_values(&arr)?;
    let pixels: Vec<[f32; 4]> = values
        .chunks_exact(c)
        .map(|p| [p[0], p[1], p[2], if c == 4 { p[3] } else { 1.0 }])
        .collect();
    Ok(Framebuffer {
        width: w,
        height: h,
        pixels,
        transparent,
    })
}

/// save(image, path, *, transparent=False): writes an (h, w, 4) (or (h, w, 3)) float array
/// as `render` returns it to an image file of any output format (by extension: .pfm, .png,
/// .tiff, .exr, .rgb, …), as the script's render commands write it. transparent=True writes
/// straight alpha, as after `background none`.
#[pyfunction]
#[pyo3(signature = (image, path, *, transparent=false))]
fn save(
    py: Python<'_>,
    image: &Bound<'_, PyAny>,
    path: PathBuf,
    transparent: bool,
) -> PyResult<()> {
    let fb = framebuffer_of(py, image, transparent)?;
    py.detach(|| write_image(&fb, &path)).map_err(py_err)
}

/// run_script(path_or_text): runs a VoRANG (Tcl) script file, or script text, as `vorang
/// script.tcl` / `vorang -e` do; messages go to stdout/stderr. Only in builds with the
/// `script` feature, which links libtcl; the default package runs the `vorang` program instead
/// (python/vorang/__init__.py). Raises OSError for a missing
/// script file and RuntimeError ("file:line: message") when the script fails.
#[cfg(feature = "script")]
#[pyfunction]
fn run_script(py: Python<'_>, path_or_text: &Bound<'_, PyAny>) -> PyResult<()> {
    use pyo3::exceptions::PyRuntimeError;
    use pyo3::types::PyString;
    use std::path::Path;
    let (is_file, text): (bool, String) = if let Ok(s) = path_or_text.cast::<PyString>() {
        let s = s.to_string();
        let one_line = !s.contains('\n');
        let p = Path::new(&s);
        if one_line && p.is_file() {
            (true, s)
        } else if one_line && s.trim_end().ends_with(".tcl") {
            return Err(PyOSError::new_err(format!("{s}: no such script file")));
        } else {
            (false, s)
        }
    } else {
        let p: PathBuf = path_or_text.extract()?;
        if !p.is_file() {
            return Err(PyOSError::new_err(format!(
                "{}: no such script file",
                p.display()
            )));
        }
        (true, p.display().to_string())
    };
    // The interpreter is not thread-safe: it runs on this thread, holding the GIL.
    let _ = py;
    let mut runner = vorang_tcl::script::Runner::new(Box::new(vorang_tcl::script::Terminal));
    let result = if is_file {
        runner.run_file(Path::new(&text))
    } else {
        runner.run_string(&text, "<script>").map(|_| ())
    };
    result.map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// _encode(image, ext, *, transparent=False) -> bytes: the image as a file of format `ext`
/// holds it (e.g. the PNG the CLI writes), for `vorang.Image._repr_png_`.
#[pyfunction]
#[pyo3(signature = (image, ext, *, transparent=false))]
fn _encode<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    ext: &str,
    transparent: bool,
) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
    let fb = framebuffer_of(py, image, transparent)?;
    let bytes = py
        .detach(|| vorang::framebuffer::encode_image(&fb, ext))
        .map_err(py_err)?;
    Ok(pyo3::types::PyBytes::new(py, &bytes))
}

#[pymodule]
fn _vorang(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyVolume>()?;
    m.add_class::<series::PySeries>()?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::animate, m)?)?;
    m.add_function(wrap_pyfunction!(save, m)?)?;
    m.add_function(wrap_pyfunction!(_encode, m)?)?;
    #[cfg(feature = "script")]
    m.add_function(wrap_pyfunction!(run_script, m)?)?;
    Ok(())
}
