//! Data: `volume`, `data`, `save_volume`, `save_subset` (thesis A.1 „Angaben zu den Daten“).

use super::{Call, CommandInfo};
use crate::script::Context;
use vorang::hypermesh::{Encoding, Layout, WriteOptions};

pub const VOLUME: CommandInfo = CommandInfo {
    name: "volume",
    usage: "file",
    summary: "load a grid with its data (HyperMesh, VTK .vtu/.vtk, Gmsh .msh, Exodus II .e/.exo, XDMF .xdmf, VTKHDF .vtkhdf, or a collection: .pvd, .pvtu, .vtm, .series); mappings, transforms and camera return to their defaults",
    details: "If the file cannot be read, the previous volume stays loaded. A collection loads its time step 0 (pieces and blocks merged) and says how many steps it has and their time range; 'timestep' shows the others.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=1)?;
        let (summary, notices) = s.session.load_volume(&c.path(0))?;
        s.report(notices);
        Ok(summary)
    },
};

pub const DATA: CommandInfo = CommandInfo {
    name: "data",
    usage: "?+? file",
    summary: "load the fields of a data-only HyperMesh file onto the grid: 'data f' replaces all fields (and resets the mappings), 'data + f' adds them",
    details: "The file's counts must match the grid. On an error nothing changes.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=2)?;
        let append = c.args().len() == 2;
        if append && c.args()[0] != "+" {
            return Err(c.wrong_args());
        }
        let path = c.path(if append { 1 } else { 0 });
        let (summary, notices) = s.session.load_data(&path, append)?;
        s.report(notices);
        Ok(summary)
    },
};

/// `binary`, `ascii`, `small` options after the file name.
fn options(c: &Call, from: usize, allow_small: bool) -> Result<WriteOptions, String> {
    let mut o = WriteOptions::default();
    for w in &c.args()[from..] {
        match w.as_str() {
            "binary" => o.encoding = Encoding::Binary,
            "ascii" => o.encoding = Encoding::Ascii,
            "small" if allow_small => o.layout = Layout::Small,
            other => {
                return Err(format!(
                    "{}: unknown option '{other}': {}",
                    c.info.name,
                    c.wrong_args()
                ));
            }
        }
    }
    Ok(o)
}

pub const SAVE_VOLUME: CommandInfo = CommandInfo {
    name: "save_volume",
    usage: "file ?binary|ascii? ?small?",
    summary: "write the volume as HyperMesh: full layout (nodes, triangles, tetrahedra by triangles, data) or small (nodes, tetrahedra by nodes, data-carrying elements); a name ending in .vtu writes VTK XML (binary appended, zlib)",
    details: "Default: ascii, full layout. Writing then reading gives back the same grid and fields. For .vtu, node data become point arrays and cell data cell arrays (named after their fields), and VoRANG's layout in the file's FieldData keeps everything else (edges, triangles, other data, Materials, denominators, every field in its place), so the .vtu reads back as the same volume.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=3)?;
        let opts = options(c, 1, true)?;
        let path = c.path(0);
        let notices = s.session.save_volume(&path, opts, c.args().len() > 1)?;
        s.report(notices);
        Ok(path.display().to_string())
    },
};

pub const SAVE_SUBSET: CommandInfo = CommandInfo {
    name: "save_subset",
    usage: "file field ?binary|ascii?",
    summary: "write the cells where the Constant field 'field' is not zero, in the small layout",
    details: "Default: ascii.",
    run: |s: &mut Context, c: &Call| {
        c.expect(2..=3)?;
        let field = c.count(1, "field")?;
        let opts = options(c, 2, false)?;
        let path = c.path(0);
        s.session.save_subset(&path, field, opts.encoding)?;
        Ok(path.display().to_string())
    },
};
