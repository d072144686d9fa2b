//! Data: `volume`, `data`, `save_volume`, `save_subset` (thesis A.1 „Angaben zu den Daten“).

use std::sync::Arc;

use super::{Call, CommandInfo};
use vorang::hypermesh::{self, Encoding, Layout, WriteOptions};
use vorang::mapping::{AlphaMap, ColorMap};
use vorang::scene::View;
use crate::script::Session;
use vorang::volume::Volume;

pub const VOLUME: CommandInfo = CommandInfo {
    name: "volume",
    usage: "file",
    summary: "load a grid with its data (HyperMesh, VTK .vtu/.vtk or Gmsh .msh); mappings, transforms and camera return to their defaults",
    details: "If the file cannot be read, the previous volume stays loaded.",
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=1)?;
        let (vol, warnings) = Volume::load(&c.path(0)).map_err(|e| e.to_string())?;
        for w in warnings {
            s.reporter.warn(&w.to_string());
        }
        let summary = format!(
            "{} nodes, {} tetrahedra, {} field{}",
            vol.mesh.node_count(),
            vol.mesh.tet_count(),
            vol.data.fields.len(),
            if vol.data.fields.len() == 1 { "" } else { "s" }
        );
        s.volume = Some(Arc::new(vol));
        s.colormap = ColorMap::default_map();
        s.alphamap = AlphaMap::default_map();
        s.view = View::default();
        Ok(summary)
    },
};

pub const DATA: CommandInfo = CommandInfo {
    name: "data",
    usage: "?+? file",
    summary: "load the fields of a data-only HyperMesh file onto the grid: 'data f' replaces all fields (and resets the mappings), 'data + f' adds them",
    details: "The file's counts must match the grid. On an error nothing changes.",
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=2)?;
        let append = c.args().len() == 2;
        if append && c.args()[0] != "+" {
            return Err(c.wrong_args());
        }
        let Some(vol) = s.volume.as_mut() else {
            return Err("data: no volume loaded: use 'volume file' first".into());
        };
        let path = c.path(if append { 1 } else { 0 });
        if let Some(desc) =
            vorang::formats::read_description_file(&path).map_err(|e| e.to_string())?
        {
            let (other, warnings) =
                vorang::formats::build::volume(desc).map_err(|e| e.to_string())?;
            let mut next = (**vol).clone();
            next.attach_fields_of(other, append)
                .map_err(|e| e.to_string())?;
            let fields = next.data.fields.len();
            *vol = Arc::new(next);
            for w in warnings {
                s.reporter.warn(&w.to_string());
            }
            if !append {
                s.colormap = ColorMap::default_map();
                s.alphamap = AlphaMap::default_map();
            }
            return Ok(format!(
                "{fields} field{}",
                if fields == 1 { "" } else { "s" }
            ));
        }
        let file = hypermesh::read_file(&path).map_err(|e| e.to_string())?;
        if file.geometry.is_some() {
            return Err(format!(
                "data: {} holds a grid; 'data' loads data-only files (use 'volume' for a grid with its data)",
                file.name
            ));
        }
        let warnings = file.warnings.clone();
        let mut next = (**vol).clone();
        next.attach_data(file, append).map_err(|e| e.to_string())?;
        let fields = next.data.fields.len();
        *vol = Arc::new(next);
        for w in warnings {
            s.reporter.warn(&w.to_string());
        }
        if !append {
            s.colormap = ColorMap::default_map();
            s.alphamap = AlphaMap::default_map();
        }
        Ok(format!(
            "{fields} field{}",
            if fields == 1 { "" } else { "s" }
        ))
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
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=3)?;
        let opts = options(c, 1, true)?;
        let vol = s
            .volume
            .as_ref()
            .ok_or("save_volume: no volume loaded: use 'volume file' first")?;
        let path = c.path(0);
        let format = vorang::formats::format_for_writing(&path);
        if format.name != "HyperMesh" && c.args().len() > 1 {
            return Err(format!(
                "save_volume: binary/ascii/small choose the HyperMesh encoding; {} is written as {} (binary appended, zlib)",
                path.display(),
                format.name
            ));
        }
        let warnings = vorang::formats::save_volume(vol, &path, opts).map_err(|e| e.to_string())?;
        for w in warnings {
            s.reporter.warn(&w.to_string());
        }
        Ok(path.display().to_string())
    },
};

pub const SAVE_SUBSET: CommandInfo = CommandInfo {
    name: "save_subset",
    usage: "file field ?binary|ascii?",
    summary: "write the cells where the Constant field 'field' is not zero, in the small layout",
    details: "Default: ascii.",
    run: |s: &mut Session, c: &Call| {
        c.expect(2..=3)?;
        let field = c.count(1, "field")?;
        let opts = options(c, 2, false)?;
        let vol = s
            .volume
            .as_ref()
            .ok_or("save_subset: no volume loaded: use 'volume file' first")?;
        let path = c.path(0);
        hypermesh::save_subset(vol, &path, field, opts.encoding).map_err(|e| e.to_string())?;
        Ok(path.display().to_string())
    },
};
