//! A volume written as a parallel grid: one `.vtu` per piece and the `.pvtu` that lists them
//! (`vorang convert IN OUT.pvtu --pieces N`) — input for `mpirun -np N vorang`, the tests and
//! the benchmarks (docs/distributed.md).

use std::path::{Path, PathBuf};

use super::partition::morton_part;
use crate::error::{Error, Warning};
use crate::formats::hypermesh::WriteOptions;
use crate::volume::{Volume, select};

/// `n` pieces of `vol`: its cells cut into `n` runs of equal length in Morton order (a solver's
/// domain decomposition looks much like this: compact pieces).
pub fn morton_pieces(vol: &Volume, n: usize) -> Vec<Vec<u32>> {
    let all: Vec<u32> = (0..vol.mesh.tet_count() as u32).collect();
    (0..n.max(1))
        .map(|p| morton_part(vol, &all, p, n.max(1)))
        .collect()
}

/// Writes `vol` as the parallel grid `path` (`.pvtu`): piece `k` (the cells `pieces[k]`, with
/// the nodes and data they use) to `STEM/STEM_k.vtu` beside it.
pub fn write_pvtu(vol: &Volume, path: &Path, pieces: &[Vec<u32>]) -> Result<Vec<Warning>, Error> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "pieces".into());
    let dir: PathBuf = path.with_file_name(&stem);
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let mut warnings = Vec::new();
    let mut listed = String::new();
    for (k, tets) in pieces.iter().enumerate() {
        let name = format!("{stem}_{k}.vtu");
        let piece = select(vol, tets.clone(), None)?;
        warnings.extend(crate::formats::save_volume(
            &piece,
            &dir.join(&name),
            WriteOptions::default(),
        )?);
        listed.push_str(&format!("    <Piece Source=\"{stem}/{name}\"/>\n"));
    }
    let text = format!(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n{listed}  </PUnstructuredGrid>\n</VTKFile>\n"
    );
    std::fs::write(path, text).map_err(|e| Error::io(path, e))?;
    Ok(warnings)
}
