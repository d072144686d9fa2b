//! The report printed by `vorang info FILE`: counts, bounding box, boundary, orientation fixes,
//! materials and every field with its type, interpolator and value range.

use std::fmt::Write as _;

use crate::data::RawData;
use crate::field::Field;
use crate::volume::{DataSet, Volume};

/// A short float for reports (about 6 significant digits).
pub fn num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-4..1e6).contains(&a) {
        let int_digits = (a.log10().floor() as i32 + 1).max(0) as usize;
        let decimals = 6usize.saturating_sub(int_digits);
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.5e}")
    }
}

fn source_desc(data: &DataSet, f: &Field) -> String {
    f.sources
        .iter()
        .map(|&s| {
            let r: &RawData = &data.raw[s];
            match &r.denominator {
                Some(d) => format!("{} {} {d}", r.kind.data_keyword(), r.ty),
                None => format!("{} {}", r.kind.data_keyword(), r.ty),
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The report for a HyperMesh volume file (geometry and data); `encoding` is e.g. `ASCII 0.7`.
pub fn describe_volume(vol: &Volume, encoding: &str) -> String {
    describe_volume_as(vol, &format!("HyperMesh {encoding}"))
}

/// The report for a volume read from a file of the given format (e.g. `VTK XML
/// UnstructuredGrid`).
pub fn describe_volume_as(vol: &Volume, format: &str) -> String {
    describe_volume_over(vol, format, None)
}

/// Each field's range per component (`None` for fields without one), as a collection's
/// report gives them over all its steps.
pub type Ranges = [Option<Vec<(f64, f64)>>];

/// [`describe_volume_as`], with the fields' ranges given (`over`: a time series' ranges over
/// all its steps) instead of taken from the volume.
fn describe_volume_over(vol: &Volume, format: &str, over: Option<(&Ranges, usize)>) -> String {
    let mut s = String::new();
    let m = &vol.mesh;
    let _ = writeln!(s, "file         {} ({format})", vol.source);
    let _ = writeln!(s, "nodes        {}", m.node_count());
    let _ = writeln!(s, "tetrahedra   {}", m.tet_count());
    if let Some(e) = &vol.edges {
        let _ = writeln!(s, "edges        {}", e.len());
    }
    if let Some(t) = &vol.triangles {
        let _ = writeln!(s, "triangles    {}", t.len());
    }
    let _ = writeln!(s, "boundary     {} faces", m.boundary_face_count());
    let _ = writeln!(s, "orientation  {} tetrahedra re-oriented", m.reoriented());
    let b = m.bbox();
    let _ = writeln!(
        s,
        "bounding box [{}, {}] × [{}, {}] × [{}, {}]",
        num(b.min[0]),
        num(b.max[0]),
        num(b.min[1]),
        num(b.max[1]),
        num(b.min[2]),
        num(b.max[2])
    );
    let c = b.center();
    let _ = writeln!(s, "centre       {} {} {}", num(c[0]), num(c[1]), num(c[2]));
    let (mut total, mut lo, mut hi) = (0.0, f64::INFINITY, 0.0f64);
    for t in 0..m.tet_count() {
        let v = m.tet_volume(t);
        total += v;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if m.tet_count() > 0 {
        let _ = writeln!(
            s,
            "volume       {} (cells {} … {})",
            num(total),
            num(lo),
            num(hi)
        );
    }
    describe_data(&mut s, &vol.data, Some(vol), over);
    s
}

/// The report for a collection (`vorang info flow.pvd`): its steps with their times and files,
/// then step 0 with every field's range over all steps (`ranges`), which the `try` line uses.
pub fn describe_series(
    vol: &Volume,
    series: &crate::formats::collection::Series,
    ranges: &Ranges,
) -> String {
    let mut s = String::new();
    let (first, last) = series.time_range();
    let kind = series.kind.noun();
    let _ = writeln!(s, "collection   {} ({kind})", series.source);
    let _ = writeln!(
        s,
        "steps        {}, t = {} … {}",
        series.len(),
        num(first),
        num(last)
    );
    for (i, step) in series.steps.iter().enumerate() {
        let files: Vec<String> = step.parts.iter().map(|p| p.label()).collect();
        let _ = writeln!(
            s,
            "  {i:>4}  t = {:<12} {}",
            num(step.time),
            files.join(", ")
        );
    }
    s.push_str(&describe_volume_over(
        vol,
        "step 0",
        Some((ranges, series.len())),
    ));
    s
}

/// The report for a data-only file (`label` names its format, e.g. `HyperMesh ASCII 0.7`).
pub fn describe_data_only(name: &str, label: &str, data: &DataSet) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "file         {name} ({label}, data only)");
    for kind in crate::data::ElementKind::ALL {
        if let Some(n) = data.counts[kind.index()] {
            let _ = writeln!(s, "{:<12} {n}", kind.count_keyword());
        }
    }
    describe_data(&mut s, data, None, None);
    s
}

/// The report for any file VoRANG reads (one lookup in the format registry), with the overlap
/// check of `--check`; `false` when that check found overlapping cells.
pub fn describe(described: &crate::formats::Described, check: bool) -> (String, bool) {
    match described {
        crate::formats::Described::Volume { volume, label } => {
            let mut text = describe_volume_as(volume, label);
            let mut clean = true;
            if check {
                let (line, ok) = check_overlaps(&volume.mesh);
                text.push_str(&line);
                clean = ok;
            }
            (text, clean)
        }
        crate::formats::Described::Data { name, label, data } => {
            (describe_data_only(name, label, data), true)
        }
        crate::formats::Described::Series {
            volume,
            series,
            ranges,
        } => {
            let mut text = describe_series(volume, series, ranges);
            let mut clean = true;
            if check {
                let (line, ok) = check_overlaps(&volume.mesh);
                text.push_str(&line);
                clean = ok;
            }
            (text, clean)
        }
    }
}

/// The fields of `data` with their ranges: the volume's own, or `over` (ranges over the
/// given number of time steps).
fn describe_data(
    s: &mut String,
    data: &DataSet,
    vol: Option<&Volume>,
    over: Option<(&Ranges, usize)>,
) {
    if let Some(mats) = &data.materials {
        let _ = writeln!(s, "materials    {}", mats.list.len());
        for m in &mats.list {
            let props: Vec<String> = m.props.iter().map(|(k, v)| format!("{k}={v}")).collect();
            let _ = writeln!(s, "  {:>3} {:<16} {}", m.id, m.name, props.join(" "));
        }
    }
    let _ = writeln!(
        s,
        "raw data     {} block{}",
        data.raw.len(),
        if data.raw.len() == 1 { "" } else { "s" }
    );
    let _ = writeln!(s, "fields       {}", data.fields.len());
    for (i, f) in data.fields.iter().enumerate() {
        let name = f
            .name
            .as_deref()
            .map(|n| format!("\"{n}\" "))
            .unwrap_or_default();
        let denom = f
            .denominator
            .as_deref()
            .map(|d| format!(" {d}"))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "  {i}: {name}{{ {}{denom} }} = {}  [{}]",
            f.ty,
            f.interpolator.name(),
            source_desc(data, f)
        );
        if let Some(parts) = vol.and_then(|v| crate::mapping::part_ranges(v, i)) {
            // Complex: each part's range, and a first picture of the modulus.
            let mut line = String::from("     range");
            for (part, range) in crate::mapping::Part::ALL.iter().zip(&parts) {
                let _ = write!(line, " {}", part.keyword());
                for (a, b) in range {
                    let _ = write!(line, " [{}, {}]", num(*a), num(*b));
                }
            }
            let _ = writeln!(s, "{line}");
            if let (Some(v), [(lo, hi)]) = (vol, parts[2].as_slice())
                && let Some(line) = first_picture(v, &format!("abs({i})"), *lo, *hi)
            {
                let _ = writeln!(s, "     try   {line}");
            }
        } else if let Some(range) = match over {
            Some((ranges, _)) => ranges.get(i).cloned().flatten(),
            None => vol.and_then(|v| v.field_range(i)),
        } {
            let parts: Vec<String> = range
                .iter()
                .map(|(a, b)| format!("[{}, {}]", num(*a), num(*b)))
                .collect();
            let steps = over.map_or(String::new(), |(_, n)| format!(" over all {n} steps"));
            let _ = writeln!(s, "     range {}{steps}", parts.join(" "));
            if let (Some(v), [(lo, hi)]) = (vol, range.as_slice())
                && let Some(line) = first_picture(v, &i.to_string(), *lo, *hi)
            {
                let _ = writeln!(s, "     try   {line}");
            }
        }
    }
}

/// A ready-to-paste first picture of scalar field `i` (a number, or a complex field's part
/// such as `abs(2)`) over its range `[lo, hi]`:
/// the viridis preset over the range and an absorption ramp up to χ = 4 / the bounding box's
/// diagonal (the densest part then lets through about e^-4 of the light across the volume),
/// with the brightness factor χ_max, so that opaque parts show the preset's colours, and no grid
/// lines (the script's default draws every edge, which hides the volume of a large mesh). `None`
/// for a constant field.
pub fn first_picture(vol: &Volume, i: &str, lo: f64, hi: f64) -> Option<String> {
    // Short numbers where they stay distinct, exact ones otherwise.
    let (a, b) = match (num(lo), num(hi)) {
        (a, b) if a.parse::<f64>().ok()? < b.parse::<f64>().ok()? => (a, b),
        _ if lo < hi => (format!("{lo}"), format!("{hi}")),
        _ => return None,
    };
    let size = vol.mesh.bbox().size();
    let diagonal = size.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(diagonal > 0.0 && diagonal.is_finite()) {
        return None;
    }
    let chi = num(4.0 / diagonal);
    Some(format!(
        "colormap preset viridis {a} {b} {i}; alphamap ramp {a} {b} {chi} {i}; method interpolateColor {chi}; linedraw off"
    ))
}

/// `vorang info --check`: cells that interpenetrate without sharing a face (at most 200 exact
/// pair tests per cell). The report line, and whether the mesh passed.
pub fn check_overlaps(mesh: &crate::mesh::TetMesh) -> (String, bool) {
    let budget = mesh.tet_count().saturating_mul(200).max(1000);
    let r = crate::mesh::overlap::find_overlaps(mesh, budget, 5);
    let scope = if r.complete {
        format!("{} candidate pairs tested", r.tested)
    } else {
        format!(
            "stopped after {} candidate pairs (the budget of 200 per cell): the check is incomplete",
            r.tested
        )
    };
    if r.found == 0 {
        return (
            format!("check        no interpenetrating cells ({scope})\n"),
            true,
        );
    }
    let examples: Vec<String> = r
        .pairs
        .iter()
        .map(|(a, b)| format!("{} and {}", a + 1, b + 1))
        .collect();
    (
        format!(
            "check        {} pairs of cells interpenetrate, e.g. cells {} ({scope}): overlapping parts are integrated twice\n",
            r.found,
            examples.join(", ")
        ),
        false,
    )
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn numbers_are_short() {
        assert_eq!(num(0.0), "0");
        assert_eq!(num(1.0), "1");
        assert_eq!(num(0.5), "0.5");
        assert_eq!(num(-2.25), "-2.25");
        assert_eq!(num(123456.0), "123456");
        assert_eq!(num(1.0 / 3.0), "0.333333");
        assert_eq!(num(1e-7), "1.00000e-7");
    }
}
