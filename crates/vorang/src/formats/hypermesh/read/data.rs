//! Resolving the data: every data block becomes raw data, and every `Field` line a field over
//! its raw data (thesis 6.1.2 and B.2, the field declarations), built and checked by its
//! interpolator. The last phase, after the geometry, because a field is checked against the
//! element counts and the materials the header declares.

use super::super::header::{Header, Target};
use super::Block;
use crate::data::RawData;
use crate::error::ParseError;
use crate::field::{Field, Interpolator, Origin};
use crate::volume::DataSet;

pub(super) fn resolve_data(
    file: &str,
    header: &Header,
    blocks: &mut [Option<Block>],
    field_blocks: &[(Interpolator, Vec<usize>)],
) -> Result<DataSet, ParseError> {
    let mut raw = Vec::new();
    let mut raw_of_decl = vec![usize::MAX; header.blocks.len()];
    for (i, (d, b)) in header.blocks.iter().zip(blocks.iter_mut()).enumerate() {
        if let Target::Data(kind) = d.target {
            let Some(b) = b.take() else { continue };
            raw_of_decl[i] = raw.len();
            raw.push(RawData {
                kind,
                ty: d.ty,
                denominator: d.denominator.clone(),
                values: b.values,
            });
        }
    }
    let mut fields = Vec::with_capacity(header.fields.len());
    for (f, (interp, decls)) in header.fields.iter().zip(field_blocks) {
        let origin = Origin {
            file: file.to_string(),
            line: f.line,
        };
        let field = Field::build(
            f.name.clone(),
            f.ty,
            f.denominator.clone(),
            *interp,
            decls.iter().map(|&d| raw_of_decl[d]).collect(),
            &raw,
            header.materials.as_ref(),
            origin,
            &|k| format!("@{}", f.markers[k]),
        )
        .map_err(|msg| ParseError::new(file, f.line, msg))?;
        fields.push(field);
    }
    Ok(DataSet {
        materials: header.materials.clone(),
        counts: header.counts.map(|c| c.map(|c| c.value)),
        count_lines: header.counts.map(|c| c.map(|c| c.line)),
        raw,
        fields,
    })
}
