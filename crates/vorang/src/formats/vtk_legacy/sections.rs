//! The keywords of a legacy VTK file, one function each: `POINTS`, `CELLS` (classic list or
//! 5.1's `OFFSETS`/`CONNECTIVITY`), `CELL_TYPES`, `POINT_DATA`/`CELL_DATA`, the attributes
//! (`SCALARS`, `VECTORS`, …), `FIELD`, and what is read past (`LOOKUP_TABLE`, `METADATA`). The
//! cells are only collected here; they are checked and built once every keyword is read
//! (`cells`), because `CELL_TYPES` may come after `CELLS`.

use super::Sections;
use super::values::{Reader, Ty};
use crate::error::ParseError;
use crate::formats::{Array, ArrayValues};

impl Sections {
    /// One keyword (`kw`, at `line`) and everything that belongs to it.
    pub(super) fn keyword(
        &mut self,
        r: &mut Reader,
        kw: &str,
        line: usize,
    ) -> Result<(), ParseError> {
        let up = kw.to_ascii_uppercase();
        match up.as_str() {
            "POINTS" => self.points(r, line),
            "CELLS" if self.version >= 5.0 => self.offsets_and_connectivity(r, line),
            "CELLS" => self.cell_list(r, line),
            "CELL_TYPES" => {
                let n = r.c.count("the number of cell types", 0)?;
                let ArrayValues::Int(v) = r.values(Ty::Int(4, true), n, "CELL_TYPES")? else {
                    unreachable!("integer type gives integers")
                };
                self.types = Some((v, line));
                Ok(())
            }
            "POINT_DATA" | "CELL_DATA" => {
                self.section = if up == "POINT_DATA" { 1 } else { 2 };
                self.section_n = r.c.count("the number of values", 0)?;
                Ok(())
            }
            "SCALARS"
            | "VECTORS"
            | "NORMALS"
            | "TENSORS"
            | "TEXTURE_COORDINATES"
            | "COLOR_SCALARS" => self.attribute(r, kw, &up, line),
            "FIELD" => {
                r.c.expect_token("the FIELD name")?;
                let n = r.c.count("the number of FIELD arrays", 0)?;
                let arrays = r.field_arrays(n)?;
                match self.section {
                    1 => self.desc.point_arrays.extend(arrays),
                    2 => self.desc.cell_arrays.extend(arrays),
                    // Dataset-level field data (TIME, CYCLE): not attached to points or cells.
                    _ => {}
                }
                Ok(())
            }
            "LOOKUP_TABLE" => {
                r.c.expect_token("the lookup table name")?;
                let n = r.c.count("the lookup table size", 0)?;
                let ty = if r.binary { Ty::Int(1, false) } else { Ty::F32 };
                r.values(ty, n.saturating_mul(4), "LOOKUP_TABLE")?;
                Ok(())
            }
            "METADATA" => {
                // Read past up to the blank line that ends it.
                r.c.next_line();
                while !r.c.at_end() {
                    if r.c.rest_of_line().trim().is_empty() {
                        break;
                    }
                }
                Ok(())
            }
            _ => Err(r.c.err_at(
                line,
                format!(
                    "unexpected '{kw}': expected POINTS, CELLS, CELL_TYPES, POINT_DATA, CELL_DATA, SCALARS, VECTORS or FIELD"
                ),
            )),
        }
    }

    fn points(&mut self, r: &mut Reader, line: usize) -> Result<(), ParseError> {
        let desc = &mut self.desc;
        let n = r.c.count("the number of points", 0)?;
        let ty = r.ty()?;
        desc.float_coordinates = ty == Ty::F32;
        desc.points_line = line;
        let v = r.values(ty, n.saturating_mul(3), "POINTS")?;
        desc.nodes = (0..n)
            .map(|i| [0, 1, 2].map(|k| v.get(3 * i + k)))
            .collect();
        self.have_points = true;
        r.skip_metadata();
        Ok(())
    }

    /// 5.x `CELLS n_offsets n_connectivity`, then the `OFFSETS` and `CONNECTIVITY` arrays.
    fn offsets_and_connectivity(&mut self, r: &mut Reader, line: usize) -> Result<(), ParseError> {
        let n_off = r.c.count("the number of offsets", 0)?;
        let n_conn = r.c.count("the connectivity size", 0)?;
        self.desc.cells_line = line;
        for _ in 0..2 {
            let (w, l) = r.c.expect_token("OFFSETS or CONNECTIVITY")?;
            let ty = r.ty()?;
            match w.to_ascii_uppercase().as_str() {
                "OFFSETS" => {
                    let ArrayValues::Int(v) = r.values(ty, n_off, "OFFSETS")? else {
                        return Err(r.c.err_at(l, "OFFSETS must be integers"));
                    };
                    self.offsets = Some(v);
                }
                "CONNECTIVITY" => {
                    let ArrayValues::Int(v) = r.values(ty, n_conn, "CONNECTIVITY")? else {
                        return Err(r.c.err_at(l, "CONNECTIVITY must be integers"));
                    };
                    self.connectivity = Some(v);
                }
                _ => {
                    return Err(r
                        .c
                        .err_at(l, format!("expected OFFSETS or CONNECTIVITY, found '{w}'")));
                }
            }
        }
        Ok(())
    }

    /// The classic `CELLS n size` list of `npts i0 i1 …`.
    fn cell_list(&mut self, r: &mut Reader, line: usize) -> Result<(), ParseError> {
        let n = r.c.count("the number of cells", 0)?;
        let size = r.c.count("the cell list size", 0)?;
        self.desc.cells_line = line;
        let ArrayValues::Int(v) = r.values(Ty::Int(4, true), size, "CELLS")? else {
            unreachable!("integer type gives integers")
        };
        self.legacy_cells = Some((v, n, line));
        Ok(())
    }

    /// An attribute array (`kw`, upper case `up`) of the current POINT_DATA or CELL_DATA.
    fn attribute(
        &mut self,
        r: &mut Reader,
        kw: &str,
        up: &str,
        line: usize,
    ) -> Result<(), ParseError> {
        if self.section == 0 {
            return Err(r
                .c
                .err_at(line, format!("{kw} before POINT_DATA or CELL_DATA")));
        }
        let (aname, _) = r.c.expect_token("the array name")?;
        let aname = aname.to_string();
        let (ty, comps) = match up {
            "SCALARS" => scalars_header(r, line)?,
            "VECTORS" | "NORMALS" => (r.ty()?, 3),
            "TENSORS" => (r.ty()?, 9),
            "TEXTURE_COORDINATES" => {
                let d = r.c.count("the texture dimension", 0)?;
                (r.ty()?, d.clamp(1, 3))
            }
            _ => {
                let d = r.c.count("the number of color components", 0)?;
                (if r.binary { Ty::Int(1, false) } else { Ty::F32 }, d.max(1))
            }
        };
        let values = r.values(
            ty,
            self.section_n.saturating_mul(comps),
            &format!("{kw} {aname}"),
        )?;
        r.skip_metadata();
        let a = Array {
            name: aname,
            components: comps,
            values,
            line,
        };
        if self.section == 1 {
            self.desc.point_arrays.push(a);
        } else {
            self.desc.cell_arrays.push(a);
        }
        Ok(())
    }
}

/// The rest of a `SCALARS name` line — the type and an optional component count — and the
/// `LOOKUP_TABLE name` line that usually follows.
fn scalars_header(r: &mut Reader, line: usize) -> Result<(Ty, usize), ParseError> {
    let ty = r.ty()?;
    // An optional component count on the same line.
    let save = (r.c.pos, r.c.line);
    let comps = match r.c.token() {
        Some((t, l)) if l == line => t.parse::<usize>().map_err(|_| {
            r.c.err_at(l, format!("expected the number of components, found '{t}'"))
        })?,
        _ => {
            (r.c.pos, r.c.line) = save;
            1
        }
    };
    if !(1..=4).contains(&comps) {
        return Err(r.c.err_at(
            line,
            format!("SCALARS with {comps} components: expected 1…4"),
        ));
    }
    // LOOKUP_TABLE name (optional in practice).
    let save = (r.c.pos, r.c.line);
    match r.c.token() {
        Some((t, _)) if t.eq_ignore_ascii_case("LOOKUP_TABLE") => {
            r.c.expect_token("the lookup table name")?;
        }
        _ => (r.c.pos, r.c.line) = save,
    }
    Ok((ty, comps))
}
