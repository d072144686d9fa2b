//! `colormap`, `alphamap`, `linedraw`, `legend` (thesis A.1 „Angaben zu Beleuchtung und Darstellung“).

use super::{Call, CommandInfo};
use crate::script::Context;
use vorang::legend::Place;
use vorang::mapping::{AlphaShading, ColorShading, preset_colormap, ramp_alphamap, read_map};
use vorang::render::LineDraw;
use vorang::session::Notice;

pub const COLORMAP: CommandInfo = CommandInfo {
    name: "colormap",
    usage: "file | preset name lo hi ?field?",
    summary: "the colour mapping: data → emission η (a '# VoRANG Colormap 1.0' file, or a built-in colour table over [lo, hi])",
    details: "Default without a file: constant red emission (1 0 0). Methods: CONSTANT, IDENTITY, SIMPLE_EMITTER, ABSORPTION_WEIGHTED, CONST_CELL, LIT_EMITTER (lit by addlight). 'colormap preset viridis 0 1' is a SIMPLE_EMITTER table from lo to hi (clamped outside) on field 0 or the given field (number or name); 'vorang info FILE' prints the data ranges and a line to paste. Presets:",
    run: |s: &mut Context, c: &Call| {
        let (map, warnings) =
            if c.args().first().is_some_and(|a| a == "preset") && c.args().len() > 1 {
                c.expect(4..=5)?;
                let [lo, hi] = c.numbers(2, ["lo", "hi"])?;
                preset_colormap(&c.args()[1], lo, hi, c.args().get(4).map(String::as_str))
                    .map(|m| (m, Vec::new()))
                    .map_err(|e| format!("colormap preset: {e}"))?
            } else {
                c.expect(1..=1)?;
                read_map::<dyn ColorShading>(&c.path(0)).map_err(|e| e.to_string())?
            };
        s.session.set_colormap(map)?;
        s.report(warnings.iter().map(|w| Notice::Warning(w.to_string())));
        Ok(String::new())
    },
};

pub const ALPHAMAP: CommandInfo = CommandInfo {
    name: "alphamap",
    usage: "file | ramp lo hi chi_max ?field?",
    summary: "the alpha mapping: data → absorption χ (a '# VoRANG Alphamap 1.0' file, or a linear ramp over [lo, hi])",
    details: "Default without a file: constant absorption 2. Methods: CONSTANT, SIMPLE_ABSORBER, BARY_SHADING, CONST_CELL. 'alphamap ramp 0 1 5' is a SIMPLE_ABSORBER table: χ = 0 at lo and below, chi_max at hi and above, linear in between, on field 0 or the given field. χ is per world unit: χ·length ≈ 4 is nearly opaque.",
    run: |s: &mut Context, c: &Call| {
        let (map, warnings) = if c.args().first().is_some_and(|a| a == "ramp") && c.args().len() > 1
        {
            c.expect(4..=5)?;
            let [lo, hi, chi] = c.numbers(1, ["lo", "hi", "chi_max"])?;
            ramp_alphamap(lo, hi, chi, c.args().get(4).map(String::as_str))
                .map(|m| (m, Vec::new()))
                .map_err(|e| format!("alphamap ramp: {e}"))?
        } else {
            c.expect(1..=1)?;
            read_map::<dyn AlphaShading>(&c.path(0)).map_err(|e| e.to_string())?
        };
        s.session.set_alphamap(map)?;
        s.report(warnings.iter().map(|w| Notice::Warning(w.to_string())));
        Ok(String::new())
    },
};

pub const LINEDRAW: CommandInfo = CommandInfo {
    name: "linedraw",
    usage: "on|off|field {values}",
    summary: "draw the grid's edges as opaque black lines: all, none, or those of the cells whose Constant field has one of the values",
    details: "Default: on. Lines are depth-correct: the volume in front of them dims them.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=2)?;
        let lines = match (c.args().len(), c.args()[0].as_str()) {
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
                        vorang::numbers::parse_f64(v.trim()).ok_or_else(|| {
                            format!("linedraw: expected numbers in the value list, found \"{v}\"")
                        })
                    })
                    .collect::<Result<Vec<f64>, String>>()?;
                LineDraw::Cells { field, values }
            }
            _ => return Err(c.wrong_args()),
        };
        s.session.set_lines(lines)?;
        Ok(String::new())
    },
};

pub const LEGEND: CommandInfo = CommandInfo {
    name: "legend",
    usage: "on|off ?right|left|top|bottom?",
    summary: "draw the colormap as a bar with its range and a few labelled values into every image",
    details: "Default: off; 'legend on' puts the bar on the right. The bar runs from the map's lowest table value to its highest (CONSTANT: the field's data range); colours above 1 are scaled down to the largest component. Maps with categories, IDENTITY or CONST_CELL have no single scale: the render warns and draws none.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=2)?;
        let place = match c.args().get(1) {
            None => Place::Right,
            Some(word) => Place::parse(word).ok_or_else(|| {
                format!(
                    "legend: expected a position {}, found '{word}'",
                    Place::NAMES.join(", ")
                )
            })?,
        };
        s.session.set_legend(match c.args()[0].as_str() {
            "on" => Some(place),
            "off" => None,
            other => return Err(format!("legend: expected on or off, found '{other}'")),
        });
        Ok(String::new())
    },
};

pub const LABEL: CommandInfo = CommandInfo {
    name: "label",
    usage: "format|off",
    summary: "print the shown time step into every image and movie frame: 'label \"t = %.3g s\"' (%g, %f, %e: the step's time; %d: its number); 'label off' removes it",
    details: "Default: off. The format is C's printf, as Tcl's 'format' reads it (flags, width and precision included; %% is a percent sign). White text with a black outline in the top left corner (bottom left when the legend is on top), in the legend's font. A volume that is no collection is step 0 at time 0.",
    run: |s: &mut Context, c: &Call| {
        c.expect(1..=1)?;
        let word = &c.args()[0];
        s.session.set_label((word != "off").then(|| word.clone()))?;
        Ok(String::new())
    },
};
