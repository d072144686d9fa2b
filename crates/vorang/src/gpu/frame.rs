//! One frame's inputs to the march, prepared on the CPU, and its result turned into the
//! framebuffer: the nodes on screen (the CPU renderer's own placement, sub-pixel grid
//! included) with their eye-space positions, each pixel's entries in depth order (boundary
//! faces by the watertight face rule: exact orientation and the top-left rule; cells reaching
//! in front of a perspective near plane where the CPU draws them), the grid lines' depths, the
//! frame's numbers and the transfer function. What the GPU backend cannot render yet is refused here with a message
//! that names it.

use rayon::prelude::*;

use super::color;
use super::twin::{self, Corner, NEAR_ENTRY, slot};
use crate::error::Error;
use crate::framebuffer::{Background, Framebuffer};
use crate::mapping::{Mapping, Transfer1D};
use crate::mesh::FACE_NODES;
use crate::predicates::entry_sign;
use crate::render::cell::{CellRays, EyeCell};
use crate::render::footprint::{Footprint, footprint_into};
use crate::render::raster::rasterize;
use crate::render::{Method, Order, Placed, Rect, Settings, TOUCH, lines, place_nodes};
use crate::scene::{Projector, View};
use crate::volume::Volume;

/// The methods the march integrates (`METHOD` in `march.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GpuMethod {
    /// `exact linear 0 B`: the field along the ray, cut at the transfer function's knots.
    Exact,
    /// `interpolateCoeff linear B`: η and χ mapped at the nodes, interpolated along the ray.
    InterpolateCoeff,
    /// `interpolateColor B`: the CPU's Shirley–Tuchman fans, Gouraud-shaded per pixel.
    InterpolateColor,
}

/// What the GPU renders, with its brightness; everything else says what it is not.
pub fn check_method(method: &Method) -> Result<(GpuMethod, f64), String> {
    match method {
        Method::Exact(m) if m.rule.name == "linear" && m.step == 0.0 => {
            Ok((GpuMethod::Exact, m.brightness))
        }
        Method::Exact(m) if m.rule.name == "linear" => Err(format!(
            "method exact linear {}: the GPU backend integrates whole cell intervals only (step 0: 'method exact linear 0 {}'); use 'backend cpu' for steps",
            m.step, m.brightness
        )),
        Method::Exact(m) => Err(format!(
            "method exact {}: the GPU backend has the linear rule only ('method exact linear 0 B'); use 'backend cpu' for {}",
            m.rule.name, m.rule.name
        )),
        Method::InterpolateCoeff(m) if m.rule.name == "linear" => {
            Ok((GpuMethod::InterpolateCoeff, m.brightness))
        }
        Method::InterpolateCoeff(m) => Err(format!(
            "method interpolateCoeff {}: the GPU backend has the linear rule only ('method interpolateCoeff linear B'); use 'backend cpu' for {}",
            m.rule.name, m.rule.name
        )),
        Method::InterpolateColor(m) => Ok((GpuMethod::InterpolateColor, m.brightness)),
        other => Err(format!(
            "method {}: not available on the GPU backend (it renders 'exact linear 0 B', 'interpolateCoeff linear B' and 'interpolateColor B'); use 'backend cpu'",
            other.name()
        )),
    }
}

/// The mapping as one transfer function of one field, as the GPU needs it.
pub fn check_mapping(mapping: &Mapping, vol: &Volume) -> Result<Transfer1D, String> {
    if mapping.is_lit() {
        return Err(
            "the colormap LIT_EMITTER is not available on the GPU backend yet; use 'backend cpu'"
                .into(),
        );
    }
    mapping.transfer(vol).ok_or_else(|| {
        "the GPU backend renders maps of one scalar Linear field (SIMPLE_EMITTER, ABSORPTION_WEIGHTED or CONSTANT colours; SIMPLE_ABSORBER or CONSTANT absorption; no categories); use 'backend cpu' for these maps".to_string()
    })
}

/// The march's inputs for one frame (the buffers of `march.wgsl` but the mesh).
pub struct FrameData {
    pub width: usize,
    pub height: usize,
    pub nodes: Vec<f64>,
    pub lists: Vec<u32>,
    /// Per pixel the nearest grid line's depth; `None` without lines.
    pub lines: Option<Vec<f64>>,
    pub consts: Vec<f64>,
    /// How many entries the pixels' lists hold.
    pub entries: usize,
}

/// Prepares a frame: refuses what the GPU does not render, places the nodes, lists every
/// pixel's boundary entries. `fma`: the device has an exact fused multiply-add.
pub fn prepare(
    vol: &Volume,
    mapping: &Mapping,
    view: &View,
    settings: &Settings,
    fma: bool,
) -> Result<FrameData, Error> {
    let (method, brightness) = check_method(&settings.method).map_err(Error::Invalid)?;
    let transfer = check_mapping(mapping, vol).map_err(Error::Invalid)?;
    crate::render::check_size(settings.width, settings.height).map_err(Error::Invalid)?;
    let placed = place_nodes(vol, view, settings)?;
    let (dmin, dmax) = placed.projector.depth();
    let perspective = placed.projector.is_perspective();
    if vol.mesh.tet_count() >= NEAR_ENTRY as usize / 4 {
        return Err(Error::Invalid(format!(
            "the GPU backend renders meshes of fewer than {} cells; use 'backend cpu'",
            NEAR_ENTRY / 4
        )));
    }
    let nodes = node_data(vol, &placed, &transfer, method, perspective)?;
    let stride = node_stride(method);
    let (width, height) = (settings.width, settings.height);
    let sign = i32::from(entry_sign(placed.mirrored));
    let clipped = near_clipped(vol, &placed, dmin);
    let mut hits = boundary_entries(vol, &nodes, stride, [width, height], sign, &clipped, fma);
    hits.extend(near_entries(vol, &placed, [width, height], &clipped));
    let mut lists = entry_lists(hits, width * height);
    let entries = lists.len() - (width * height + 1);
    let fans = lists.len();
    if method == GpuMethod::InterpolateColor {
        lists.extend(color::fan_codes(vol, &placed));
    }
    let edges = lines::edges(vol, &settings.lines)?;
    let line_depth = if edges.is_empty() {
        None
    } else {
        Some(lines::depth_buffer(
            &edges,
            &placed.eye_nodes,
            &placed.projector,
            width,
            height,
        )?)
    };
    let (tan_x, tan_y) = match placed.projector {
        Projector::Persp { tan_x, tan_y, .. } => (tan_x, tan_y),
        Projector::Ortho { .. } => (0.0, 0.0),
    };
    let mut consts = vec![0.0; slot::TABLE];
    consts[slot::WIDTH] = width as f64;
    consts[slot::HEIGHT] = height as f64;
    consts[slot::PERSPECTIVE] = f64::from(u8::from(perspective));
    consts[slot::ENTRY_SIGN] = f64::from(sign);
    consts[slot::FRONT_TO_BACK] = f64::from(u8::from(settings.order == Order::FrontToBack));
    consts[slot::DMIN] = dmin;
    consts[slot::DMAX] = dmax;
    consts[slot::TAN_X] = tan_x;
    consts[slot::TAN_Y] = tan_y;
    consts[slot::BRIGHTNESS] = brightness;
    consts[slot::WEIGHTED] = f64::from(u8::from(transfer.weighted()));
    consts[slot::QUADRATIC] = f64::from(u8::from(transfer.quadratic_eta()));
    consts[slot::KNOTS] = transfer.knot_count() as f64;
    consts[slot::HAS_LINES] = f64::from(u8::from(line_depth.is_some()));
    consts[slot::EXACT_FMA] = f64::from(u8::from(fma));
    consts[slot::CELLS] = vol.mesh.tet_count() as f64;
    consts[slot::NODE] = stride as f64;
    consts[slot::ANY_NEAR] = f64::from(u8::from(clipped.iter().any(|&c| c)));
    consts[slot::METHOD] = match method {
        GpuMethod::Exact => 0.0,
        GpuMethod::InterpolateCoeff => 1.0,
        GpuMethod::InterpolateColor => 2.0,
    };
    consts[slot::FANS] = fans as f64;
    consts[slot::LOOP_CHECK] = 2.0;
    let planes = placed.projector.ray_planes();
    consts[slot::MAX_SPEED] = planes.max_speed;
    consts[slot::INFINITY] = f64::INFINITY;
    for r in 0..3 {
        for k in 0..3 {
            consts[slot::PLANES + 3 * r + k] = planes.origin[r][k];
            consts[slot::PLANES + 9 + 3 * r + k] = planes.dir[r][k];
        }
    }
    consts.extend(transfer.flat());
    Ok(FrameData {
        width,
        height,
        nodes,
        lists,
        lines: line_depth,
        consts,
        entries,
    })
}

/// The numbers per node in the march's `nodes`.
fn node_stride(method: GpuMethod) -> usize {
    match method {
        GpuMethod::Exact | GpuMethod::InterpolateColor => 7,
        GpuMethod::InterpolateCoeff => 10,
    }
}

/// Per node: screen x and y, depth (orthographic) or its inverse (perspective, as
/// `render::faces` takes it), the eye-space position, then the transfer function's field
/// (exact, interpolateColor) or η and χ mapped at the node (interpolateCoeff: the CPU's
/// `Transfer1D::map_nodes`).
fn node_data(
    vol: &Volume,
    placed: &Placed,
    transfer: &Transfer1D,
    method: GpuMethod,
    perspective: bool,
) -> Result<Vec<f64>, Error> {
    let values = &transfer.node_values;
    let count = vol.mesh.node_count();
    let mapped = match method {
        GpuMethod::Exact => None,
        // The march maps the field at the nodes as Transfer1D::map_nodes does, which takes it
        // finite (else the CPU maps per cell).
        GpuMethod::InterpolateColor => {
            let finite = values.len() == count && values.iter().all(|v| v.is_finite());
            if !values.is_empty() && !finite {
                return Err(Error::Invalid(
                    "interpolateColor on the GPU needs a finite field value at every node; use 'backend cpu'"
                        .into(),
                ));
            }
            None
        }
        // As the CPU maps a cell's nodes (render::frame's `mapped`): a map of no field at 0.
        GpuMethod::InterpolateCoeff => Some(match transfer.map_nodes(count) {
            Some(m) => m,
            None if values.is_empty() => vec![transfer.eval(0.0); count],
            None => {
                return Err(Error::Invalid(
                    "interpolateCoeff on the GPU needs a finite field value at every node; use 'backend cpu'"
                        .into(),
                ));
            }
        }),
    };
    let stride = node_stride(method);
    let mut out = vec![0.0; stride * count];
    out.par_chunks_mut(stride).enumerate().for_each(|(n, o)| {
        let e = placed.eye_nodes[n];
        let d = -e[2];
        let s = placed.screen[n];
        o[0] = s[0];
        o[1] = s[1];
        o[2] = if perspective { 1.0 / d } else { d };
        o[3..6].copy_from_slice(&e);
        match &mapped {
            None => o[6] = values.get(n).copied().unwrap_or(0.0),
            Some(m) => {
                let (eta, chi) = m[n];
                o[6..9].copy_from_slice(&eta);
                o[9] = chi;
            }
        }
    });
    Ok(out)
}

/// Every pixel's boundary entries, nearest first, as the march reads them: the offsets of the
/// `width·height` pixels' lists (and the end), then the entries `4·cell + face`. A boundary face
/// seen from outside (an entry face by the exact orientation) holds the pixel centres inside
/// it under the top-left rule, as `render::faces` decides.
fn boundary_entries(
    vol: &Volume,
    nodes: &[f64],
    stride: usize,
    [width, height]: [usize; 2],
    sign: i32,
    clipped: &[bool],
    fma: bool,
) -> Vec<(u32, f64, u32)> {
    // Only perspective views mark cells (a mesh without cells has no faces either).
    let perspective = !clipped.is_empty();
    let tets = vol.mesh.tets();
    let corner = |n: u32| {
        let i = stride * n as usize;
        Corner {
            p: [nodes[i], nodes[i + 1]],
            z: nodes[i + 2],
            v: 0.0,
            id: n,
        }
    };
    let faces: Vec<(usize, usize)> = vol.mesh.boundary_faces().collect();
    faces
        .par_iter()
        .filter(|&&(cell, _)| !clipped.get(cell).copied().unwrap_or(false))
        .flat_map_iter(|&(cell, f)| {
            let k = FACE_NODES[f].map(|l| corner(tets[cell][l]));
            let s = k.map(|c| c.p);
            let o = twin::orient(s[0], s[1], s[2], fma);
            let mut out = Vec::new();
            if o * sign <= 0 {
                return out;
            }
            let pos = if o > 0 { [0, 1, 2] } else { [0, 2, 1] }.map(|i| s[i]);
            let lo = |m: f64| (m - 0.5).ceil().max(0.0);
            let hi = |m: f64, n: usize| (m - 0.5).floor().min(n as f64 - 1.0);
            let (mut x0, mut y0) = (f64::INFINITY, f64::INFINITY);
            let (mut x1, mut y1) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
            for p in s {
                (x0, y0, x1, y1) = (x0.min(p[0]), y0.min(p[1]), x1.max(p[0]), y1.max(p[1]));
            }
            let (x0, y0, x1, y1) = (lo(x0), lo(y0), hi(x1, width), hi(y1, height));
            if !(x0 <= x1 && y0 <= y1) {
                return out;
            }
            for y in y0 as usize..=y1 as usize {
                for x in x0 as usize..=x1 as usize {
                    let p = [x as f64 + 0.5, y as f64 + 0.5];
                    if (0..3).all(|e| twin::inside(pos[e], pos[(e + 1) % 3], p, fma)) {
                        let depth = twin::face_hit(k, p, perspective, fma)[0];
                        out.push(((y * width + x) as u32, depth, (4 * cell + f) as u32));
                    }
                }
            }
            out
        })
        .collect()
}

/// Per cell whether it reaches in front of the perspective near plane (`render::footprint`:
/// its pixels then come from its planes); empty for an orthographic view.
fn near_clipped(vol: &Volume, placed: &Placed, dmin: f64) -> Vec<bool> {
    if !placed.projector.is_perspective() {
        return Vec::new();
    }
    vol.mesh
        .tets()
        .par_iter()
        .map(|t| t.iter().any(|&n| -placed.eye_nodes[n as usize][2] < dmin))
        .collect()
}

/// The pixels of every near-clipped cell, as the CPU draws them (`render::tile`'s per-ray path
/// without faces): its footprint cut at the near plane, rasterized, and the ray's interval from
/// the cell's planes where it is longer than a touch; the entry's depth is where the interval
/// starts behind the near plane.
fn near_entries(
    vol: &Volume,
    placed: &Placed,
    [width, height]: [usize; 2],
    clipped: &[bool],
) -> Vec<(u32, f64, u32)> {
    let tets = vol.mesh.tets();
    let projector = &placed.projector;
    let (dmin, _) = projector.depth();
    let rect = Rect {
        x0: 0,
        y0: 0,
        x1: width,
        y1: height,
    };
    (0..clipped.len())
        .into_par_iter()
        .filter(|&c| clipped[c])
        .flat_map_iter(|cell| {
            let mut out = Vec::new();
            let ids = tets[cell];
            let eye = ids.map(|n| placed.eye_nodes[n as usize]);
            let screen = ids.map(|n| placed.screen[n as usize]);
            let mut fp = Footprint::empty();
            if !EyeCell::is_proper(&eye) || !footprint_into(ids, &eye, &screen, projector, &mut fp)
            {
                return out;
            }
            let Some(ec) = EyeCell::new(&eye) else {
                return out;
            };
            let rays = CellRays::new(&ec, projector);
            let (lo, hi) = eye
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(-p[2]), hi.max(-p[2]))
                });
            let touch = TOUCH * (hi - lo);
            for k in 0..fp.count {
                rasterize::<false>(&fp.tris[k], rect, |x, y, _| {
                    let iv = rays.interval(x as f64 + 0.5, y as f64 + 0.5);
                    if let Some(iv) = iv.filter(|iv| iv.far - iv.near > touch) {
                        let code = NEAR_ENTRY | cell as u32;
                        out.push(((y * width + x) as u32, iv.near.max(dmin), code));
                    }
                });
            }
            out
        })
        .collect()
}

/// The march's lists from every pixel's entries: the offsets of the `pixels` lists (and the
/// end), then each pixel's entries nearest first.
fn entry_lists(mut hits: Vec<(u32, f64, u32)>, pixels: usize) -> Vec<u32> {
    hits.par_sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut lists = Vec::with_capacity(pixels + 1 + hits.len());
    let mut at = 0;
    for p in 0..=pixels {
        lists.push((pixels + 1 + at) as u32);
        while at < hits.len() && hits[at].0 as usize == p {
            at += 1;
        }
    }
    lists.extend(hits.iter().map(|h| h.2));
    lists
}

/// The march's result as the framebuffer keeps it (`render::tile`'s finish for front-to-back
/// compositing): the colour with I0 behind it (black on a grid line), alpha 1 − T (1 on a line).
pub fn finish(data: &FrameData, image: &[f64], settings: &Settings) -> Result<Framebuffer, Error> {
    let (width, height) = (data.width, data.height);
    let mut fb = Framebuffer::try_new(width, height)?;
    let uniform = match &settings.background {
        Background::Color(c) => Some(*c),
        Background::None => Some([0.0; 3]),
        _ => None,
    };
    let pixels = match uniform {
        Some(_) => Vec::new(),
        None => settings.background.pixels(width, height)?,
    };
    let to_f32 = |v: f64| {
        let m = f64::from(f32::MAX);
        if v.is_finite() {
            v.clamp(-m, m) as f32
        } else {
            v as f32
        }
    };
    fb.pixels.par_iter_mut().enumerate().for_each(|(i, out)| {
        let line = data.lines.as_ref().is_some_and(|l| l[i].is_finite());
        let bg = if line {
            [0.0; 3]
        } else {
            uniform.unwrap_or_else(|| pixels[i])
        };
        let c = &image[5 * i..5 * i + 4];
        let t = c[3];
        let rgb = [0, 1, 2].map(|k| c[k] + t * bg[k]);
        let alpha = if line { 1.0 } else { 1.0 - t };
        *out = [to_f32(rgb[0]), to_f32(rgb[1]), to_f32(rgb[2]), alpha as f32];
    });
    fb.transparent = matches!(settings.background, Background::None);
    Ok(fb)
}
