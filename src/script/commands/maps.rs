//! `colormap`, `alphamap`, `linedraw` (thesis A.1 „Angaben zu Beleuchtung und Darstellung“).

use super::{Call, CommandInfo};
use crate::mapping::{AlphaMap, AlphaShading, ColorMap, ColorShading, Mapping, read_map};
use crate::render::LineDraw;
use crate::script::Session;

/// Binds the maps now if a volume is loaded, so that a mismatch is reported at the command.
fn check(s: &Session, color: &ColorMap, alpha: &AlphaMap) -> Result<(), String> {
    if let Some(vol) = &s.volume {
        Mapping::new(color, alpha, vol).map_err(|e| e.to_string())?;
    }
    Ok(())
}

pub const COLORMAP: CommandInfo = CommandInfo {
    name: "colormap",
    usage: "file",
    summary: "the colour mapping: data → emission η (a '# VoRANG Colormap 1.0' file)",
    details: "Default without a file: constant red emission (1 0 0). Methods: CONSTANT, IDENTITY, SIMPLE_EMITTER, ABSORPTION_WEIGHTED, CONST_CELL.",
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=1)?;
        let (map, warnings) =
            read_map::<dyn ColorShading>(&c.path(0)).map_err(|e| e.to_string())?;
        check(s, &map, &s.alphamap)?;
        for w in warnings {
            s.reporter.warn(&w.to_string());
        }
        s.colormap = map;
        Ok(String::new())
    },
};

pub const ALPHAMAP: CommandInfo = CommandInfo {
    name: "alphamap",
    usage: "file",
    summary: "the alpha mapping: data → absorption χ (a '# VoRANG Alphamap 1.0' file)",
    details: "Default without a file: constant absorption 2. Methods: CONSTANT, SIMPLE_ABSORBER, BARY_SHADING, CONST_CELL.",
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=1)?;
        let (map, warnings) =
            read_map::<dyn AlphaShading>(&c.path(0)).map_err(|e| e.to_string())?;
        check(s, &s.colormap, &map)?;
        for w in warnings {
            s.reporter.warn(&w.to_string());
        }
        s.alphamap = map;
        Ok(String::new())
    },
};

pub const LINEDRAW: CommandInfo = CommandInfo {
    name: "linedraw",
    usage: "on|off|field {values}",
    summary: "draw the grid's edges as opaque black lines: all, none, or those of the cells whose Constant field has one of the values",
    details: "Default: on. Lines are depth-correct: the volume in front of them dims them.",
    run: |s: &mut Session, c: &Call| {
        c.expect(1..=2)?;
        s.settings.lines = match (c.args().len(), c.args()[0].as_str()) {
            (1, "on") => LineDraw::All,
            (1, "off") => LineDraw::Off,
            (2, _) => {
                let field = c.count(0, "field")?;
                // Commas separate values too, as the thesis writes them: `{0, 7}`.
                let values = c
                    .list(1)?
                    .iter()
                    .flat_map(|v| v.split(','))
                    .filter(|v| !v.trim().is_empty())
                    .map(|v| {
                        crate::numbers::parse_f64(v.trim()).ok_or_else(|| {
                            format!("linedraw: expected numbers in the value list, found \"{v}\"")
                        })
                    })
                    .collect::<Result<Vec<f64>, String>>()?;
                if let Some(vol) = &s.volume {
                    let lines = LineDraw::Cells {
                        field,
                        values: values.clone(),
                    };
                    crate::render::lines::edges(vol, &lines).map_err(|e| e.to_string())?;
                }
                LineDraw::Cells { field, values }
            }
            _ => return Err(c.wrong_args()),
        };
        Ok(String::new())
    },
};
