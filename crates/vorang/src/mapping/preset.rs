//! Built-in transfer functions for a first picture without map files:
//! `colormap preset NAME lo hi` and `alphamap ramp lo hi chi_max`.
//!
//! Both are written as map text (a SIMPLE_EMITTER / SIMPLE_ABSORBER table over `[lo, hi]`) and
//! read by the map parser, so a preset binds, renders, merges into the 1-D transfer table and
//! reports errors exactly like the same map loaded from a file — and `preset_text` shows the
//! user that file.
//!
//! The colour tables are the published ones: matplotlib's `viridis`, `magma`, `inferno`,
//! `plasma`, `cividis` (256-entry lists) and `coolwarm` (Moreland's diverging map), sampled at
//! every 15th entry (0, 15, …, 255: 18 exact entries of the list), linear in between.

use super::parse::parse_map;
use super::{AlphaMap, AlphaShading, ColorMap, ColorShading};

/// How many knots each preset has: list entries 0, 15, …, 255.
const KNOTS: usize = 18;

/// One built-in colour table.
pub struct Preset {
    pub name: &'static str,
    pub summary: &'static str,
    /// RGB at `KNOTS` evenly spaced points from `lo` to `hi`.
    pub knots: &'static [[f64; 3]; KNOTS],
}

/// Every colour preset, for `colormap preset`, `help colormap` and the messages.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "viridis",
        summary: "dark blue → green → yellow, perceptually uniform (matplotlib's default)",
        knots: &VIRIDIS,
    },
    Preset {
        name: "magma",
        summary: "black → purple → orange → light yellow, perceptually uniform",
        knots: &MAGMA,
    },
    Preset {
        name: "inferno",
        summary: "black → purple → orange → yellow, perceptually uniform",
        knots: &INFERNO,
    },
    Preset {
        name: "plasma",
        summary: "blue → purple → orange → yellow, perceptually uniform",
        knots: &PLASMA,
    },
    Preset {
        name: "cividis",
        summary: "blue → grey → yellow, readable with colour-vision deficiency",
        knots: &CIVIDIS,
    },
    Preset {
        name: "coolwarm",
        summary: "diverging blue → light grey → red (Moreland), for values around a centre",
        knots: &COOLWARM,
    },
    Preset {
        name: "grey",
        summary: "black → white",
        knots: &GREY,
    },
];

/// The preset names, for messages.
pub fn preset_names() -> String {
    PRESETS
        .iter()
        .map(|p| p.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The preset called `name`; the error lists the names.
pub fn preset(name: &str) -> Result<&'static Preset, String> {
    PRESETS.iter().find(|p| p.name == name).ok_or_else(|| {
        format!(
            "unknown colour preset '{name}': expected one of {}",
            preset_names()
        )
    })
}

/// `lo < hi`, both finite; the knot values `lo … hi` strictly increasing (`hi` exactly).
fn knot_values(lo: f64, hi: f64, n: usize) -> Result<Vec<f64>, String> {
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(format!(
            "expected a range lo < hi of finite numbers, got {lo} … {hi}"
        ));
    }
    let last = (n - 1) as f64;
    let values: Vec<f64> = (0..n)
        .map(|k| match k {
            0 => lo,
            k if k == n - 1 => hi,
            k => lo + (hi - lo) * (k as f64 / last),
        })
        .collect();
    if values.windows(2).any(|w| w[0] >= w[1]) {
        return Err(format!(
            "the range {lo} … {hi} is too narrow for {n} distinct table values"
        ));
    }
    Ok(values)
}

/// `DataField` line for an optional field (a number, a name, or a complex field's part).
fn data_field_line(field: Option<&str>) -> Result<String, String> {
    match field {
        None => Ok(String::new()),
        Some(f) if f.parse::<usize>().is_ok() => Ok(format!("DataField {f}\n")),
        // A complex field's part, as a map file writes it: `abs(0)`, `re("E")`.
        Some(f)
            if !f.contains('\n') && super::MapField::parse(f).is_some_and(|m| m.part.is_some()) =>
        {
            Ok(format!("DataField {f}\n"))
        }
        Some(f) if !f.is_empty() && !f.contains('"') && !f.contains('\n') => {
            Ok(format!("DataField \"{f}\"\n"))
        }
        Some(f) => Err(format!("expected a field number or name, found '{f}'")),
    }
}

/// The colormap file that `colormap preset NAME lo hi ?field?` stands for.
pub fn preset_text(name: &str, lo: f64, hi: f64, field: Option<&str>) -> Result<String, String> {
    let p = preset(name)?;
    let values = knot_values(lo, hi, KNOTS)?;
    let mut s = format!(
        "# VoRANG Colormap 1.0\n# preset {name} over [{lo}, {hi}]\n{}SIMPLE_EMITTER @1\n@1\n",
        data_field_line(field)?
    );
    for (rgb, v) in p.knots.iter().zip(&values) {
        s.push_str(&format!("{} {} {} {v}\n", rgb[0], rgb[1], rgb[2]));
    }
    Ok(s)
}

/// The alphamap file that `alphamap ramp lo hi chi_max ?field?` stands for: χ = 0 at `lo`
/// (and below), `chi_max` at `hi` (and above), linear in between.
pub fn ramp_text(lo: f64, hi: f64, chi_max: f64, field: Option<&str>) -> Result<String, String> {
    if !(chi_max.is_finite() && chi_max >= 0.0) {
        return Err(format!(
            "chi_max must be a finite number ≥ 0, got {chi_max}"
        ));
    }
    knot_values(lo, hi, 2)?;
    Ok(format!(
        "# VoRANG Alphamap 1.0\n# ramp over [{lo}, {hi}] up to {chi_max}\n{}SIMPLE_ABSORBER @1\n@1\n0 {lo}\n{chi_max} {hi}\n",
        data_field_line(field)?
    ))
}

/// The colormap `colormap preset NAME lo hi ?field?` binds (labelled `preset NAME` in
/// messages).
pub fn preset_colormap(
    name: &str,
    lo: f64,
    hi: f64,
    field: Option<&str>,
) -> Result<ColorMap, String> {
    let text = preset_text(name, lo, hi, field)?;
    parse_map::<dyn ColorShading>(text.as_bytes(), &format!("preset {name}"))
        .map(|(map, _)| map)
        .map_err(|e| e.to_string())
}

/// The alphamap `alphamap ramp lo hi chi_max ?field?` binds.
pub fn ramp_alphamap(
    lo: f64,
    hi: f64,
    chi_max: f64,
    field: Option<&str>,
) -> Result<AlphaMap, String> {
    let text = ramp_text(lo, hi, chi_max, field)?;
    parse_map::<dyn AlphaShading>(text.as_bytes(), "ramp")
        .map(|(map, _)| map)
        .map_err(|e| e.to_string())
}

const GREY: [[f64; 3]; KNOTS] = {
    let mut t = [[0.0; 3]; KNOTS];
    let mut k = 0;
    while k < KNOTS {
        let v = k as f64 / (KNOTS - 1) as f64;
        t[k] = [v, v, v];
        k += 1;
    }
    t
};

// Generated from matplotlib 3.11's colormaps (`colormaps[name](range(0, 256, 15))`).
const VIRIDIS: [[f64; 3]; KNOTS] = [
    [0.267004, 0.004874, 0.329415],
    [0.281924, 0.089666, 0.412415],
    [0.280255, 0.165693, 0.476498],
    [0.263663, 0.237631, 0.518762],
    [0.237441, 0.305202, 0.541921],
    [0.208623, 0.367752, 0.552675],
    [0.182256, 0.426184, 0.55712],
    [0.159194, 0.482237, 0.558073],
    [0.13777, 0.537492, 0.554906],
    [0.121148, 0.592739, 0.544641],
    [0.128087, 0.647749, 0.523491],
    [0.180653, 0.701402, 0.488189],
    [0.274149, 0.751988, 0.436601],
    [0.395174, 0.797475, 0.367757],
    [0.535621, 0.835785, 0.281908],
    [0.688944, 0.865448, 0.182725],
    [0.845561, 0.887322, 0.099702],
    [0.993248, 0.906157, 0.143936],
];

const MAGMA: [[f64; 3]; KNOTS] = [
    [0.001462, 0.000466, 0.013866],
    [0.03552, 0.028397, 0.125209],
    [0.102815, 0.06301, 0.257854],
    [0.19146, 0.064818, 0.396152],
    [0.291366, 0.064553, 0.475462],
    [0.384299, 0.097855, 0.501002],
    [0.47578, 0.134577, 0.507921],
    [0.569172, 0.167454, 0.504105],
    [0.664915, 0.198075, 0.488836],
    [0.761077, 0.231214, 0.460162],
    [0.852126, 0.276106, 0.418573],
    [0.925937, 0.346844, 0.374959],
    [0.96968, 0.446936, 0.360311],
    [0.989363, 0.557873, 0.391671],
    [0.99658, 0.668256, 0.456192],
    [0.996727, 0.776795, 0.541039],
    [0.99244, 0.88433, 0.640099],
    [0.987053, 0.991438, 0.749504],
];

const INFERNO: [[f64; 3]; KNOTS] = [
    [0.001462, 0.000466, 0.013866],
    [0.037668, 0.025921, 0.132232],
    [0.116656, 0.047574, 0.272321],
    [0.217949, 0.036615, 0.383522],
    [0.316282, 0.05349, 0.425116],
    [0.410113, 0.087896, 0.433098],
    [0.503493, 0.121575, 0.423356],
    [0.59694, 0.154848, 0.398125],
    [0.688653, 0.192239, 0.357603],
    [0.775059, 0.239667, 0.303526],
    [0.851384, 0.30226, 0.239636],
    [0.912966, 0.381636, 0.169755],
    [0.956852, 0.475356, 0.094695],
    [0.981895, 0.579392, 0.02625],
    [0.987464, 0.690366, 0.07999],
    [0.973088, 0.805409, 0.216877],
    [0.947594, 0.917399, 0.410665],
    [0.988362, 0.998364, 0.644924],
];

const PLASMA: [[f64; 3]; KNOTS] = [
    [0.050383, 0.029803, 0.527975],
    [0.186213, 0.018803, 0.587228],
    [0.287076, 0.010855, 0.627295],
    [0.381047, 0.001814, 0.653068],
    [0.471457, 0.005678, 0.659897],
    [0.557243, 0.047331, 0.643443],
    [0.636008, 0.112092, 0.605205],
    [0.706178, 0.178437, 0.553657],
    [0.76809, 0.244817, 0.498465],
    [0.823132, 0.311261, 0.444806],
    [0.872303, 0.378774, 0.393355],
    [0.915471, 0.448807, 0.34289],
    [0.951344, 0.52285, 0.292275],
    [0.977856, 0.602051, 0.241387],
    [0.992541, 0.68703, 0.19217],
    [0.992505, 0.777967, 0.152855],
    [0.974443, 0.874622, 0.144061],
    [0.940015, 0.975158, 0.131326],
];

const CIVIDIS: [[f64; 3]; KNOTS] = [
    [0.0, 0.135112, 0.304751],
    [0.0, 0.176082, 0.407577],
    [0.087465, 0.214879, 0.437342],
    [0.180503, 0.25618, 0.427299],
    [0.247605, 0.296986, 0.422917],
    [0.305886, 0.337681, 0.424512],
    [0.359916, 0.378641, 0.431501],
    [0.411607, 0.420145, 0.443577],
    [0.461616, 0.462405, 0.461969],
    [0.514226, 0.505546, 0.47264],
    [0.570607, 0.549695, 0.469593],
    [0.628576, 0.595104, 0.459641],
    [0.687957, 0.641966, 0.442886],
    [0.748772, 0.69047, 0.418448],
    [0.811054, 0.740801, 0.385198],
    [0.875057, 0.793125, 0.339685],
    [0.941147, 0.84753, 0.275815],
    [0.995737, 0.909344, 0.217772],
];

const COOLWARM: [[f64; 3]; KNOTS] = [
    [0.2298057, 0.298717966, 0.753683153],
    [0.2994412594117647, 0.40024818329411765, 0.8398419750588235],
    [0.37355243129411764, 0.4974987054117647, 0.9094673695294118],
    [0.4517385604705882, 0.5881809882352941, 0.9602012675882352],
    [0.5325682374117646, 0.6698005978823529, 0.9903932701176471],
    [0.6139326527647059, 0.7399229822941177, 0.9991423720588235],
    [0.6933212848235294, 0.7963141317058823, 0.9863077805294118],
    [0.7680343643529411, 0.8370352195294117, 0.9524882182352941],
    [0.8353447113529412, 0.8605139972941176, 0.8989704099411765],
    [0.8958817682941177, 0.8499060565882353, 0.8234990762941177],
    [0.940878943, 0.8055964028235294, 0.7351665564705883],
    [0.9648353582352941, 0.7446136745882352, 0.6432388753529412],
    [0.968105337, 0.6684751961176472, 0.5504862209411766],
    [0.951253794882353, 0.5787993895882353, 0.4594078057647059],
    [0.9151571239411764, 0.4769265271764706, 0.3721794147647059],
    [0.8610536002941176, 0.3629157635294118, 0.2906281271764706],
    [0.7905615319411765, 0.23139699905882352, 0.21624203829411764],
    [0.705673158, 0.01555616, 0.150232812],
];
