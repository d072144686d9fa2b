//! What every tile of one frame shares: the volume and mapping, the camera, node positions in
//! eye space and on screen, and per-pixel inputs (background, line depth).

use crate::mapping::{CategoryTransfers, Mapping, Transfer1D};
use crate::scene::Projector;
use crate::volume::Volume;

/// The background intensity I0: one colour needs no per-pixel buffer.
pub enum Backdrop {
    Uniform([f64; 3]),
    Image(Vec<[f64; 3]>),
}

pub struct Frame<'a> {
    pub vol: &'a Volume,
    pub mapping: &'a Mapping,
    /// The mapping as a merged 1D transfer function, where it has that form (the fast path).
    pub transfer: Option<Transfer1D>,
    /// For a map whose categories are constant per cell (materials): a transfer function per
    /// pair of method lines, so that such cells take the fast path too.
    pub category_transfers: Option<CategoryTransfers>,
    /// η and χ mapped at every node ([`Transfer1D::map_nodes`]), for the methods that map at the nodes
    /// (`interpolateColor`, `interpolateCoeff`): once per frame instead of once per cell
    /// and node.
    pub node_mapped: Option<Vec<([f64; 3], f64)>>,
    pub projector: Projector,
    pub width: usize,
    pub height: usize,
    /// Node positions in eye space.
    pub eye_nodes: Vec<[f64; 3]>,
    /// Node positions on screen (meaningless for perspective nodes before the near plane).
    pub screen: Vec<[f64; 2]>,
    pub background: Backdrop,
    /// Depth of the nearest grid line per pixel (∞ where none); `None` when no line is drawn.
    pub line_depth: Option<Vec<f64>>,
    /// Which screen orientation makes a face an entry face ([`crate::predicates::entry_sign`]).
    pub entry_sign: i8,
    /// Each cell's place in the compositing order (empty unless the order is settled per pixel).
    pub rank: Vec<u32>,
    /// Whether cells may take the SIMD span kernels ([`super::Settings::span_kernels`]).
    pub span_kernels: bool,
}

impl Frame<'_> {
    /// η and χ at the point with barycentric coordinates `lambda` in `cell`: every needed field
    /// evaluated once with its own interpolator, then mapped. `buf` is scratch space.
    #[inline]
    pub fn mapped(&self, cell: usize, lambda: &[f64; 4], buf: &mut Vec<f64>) -> ([f64; 3], f64) {
        if let Some((t, values)) = self.transfer_of(cell) {
            return t.eval(Transfer1D::scalar(&self.gather(cell, values), lambda));
        }
        let tet = self.vol.mesh.tets()[cell];
        let nodes = self.vol.mesh.nodes();
        let mut pos = [0.0; 3];
        for i in 0..4 {
            let p = nodes[tet[i] as usize];
            for k in 0..3 {
                pos[k] += lambda[i] * p[k];
            }
        }
        buf.resize(self.mapping.width(), 0.0);
        self.mapping.sample_fields(self.vol, cell, lambda, pos, buf);
        self.mapping.eval(buf, cell, pos)
    }

    /// The transfer function's field at a cell's four nodes (zeros if it reads no field).
    #[inline]
    pub fn node_values(&self, cell: usize) -> [f64; 4] {
        match self.transfer_of(cell) {
            Some((_, values)) => self.gather(cell, values),
            None => [0.0; 4],
        }
    }

    /// A transfer function's node values at a cell's four nodes (zeros if it reads no field).
    #[inline]
    pub fn gather(&self, cell: usize, values: &[f64]) -> [f64; 4] {
        if values.is_empty() {
            [0.0; 4]
        } else {
            self.vol.mesh.gather(cell, values)
        }
    }

    /// The mapping inside `cell` as a merged 1D transfer function, with its field's node values
    /// (empty if it reads none): the frame's one, or the one of the cell's category lines.
    #[inline]
    pub fn transfer_of(&self, cell: usize) -> Option<(&Transfer1D, &[f64])> {
        if let Some(t) = &self.transfer {
            return Some((t, &t.node_values));
        }
        let per_category = self.category_transfers.as_ref()?;
        per_category.of(self.mapping.cell_lines(self.vol, cell))
    }

    /// The four corners of a cell in eye space.
    #[inline]
    pub fn eye_corners(&self, cell: usize) -> [[f64; 3]; 4] {
        self.vol.mesh.gather(cell, &self.eye_nodes)
    }

    #[inline]
    pub fn screen_corners(&self, cell: usize) -> [[f64; 2]; 4] {
        self.vol.mesh.gather(cell, &self.screen)
    }

    /// I0 at a pixel.
    #[inline]
    pub fn background_at(&self, x: usize, y: usize) -> [f64; 3] {
        match &self.background {
            Backdrop::Uniform(c) => *c,
            Backdrop::Image(px) => px[y * self.width + x],
        }
    }

    /// The depth of the nearest grid line at a pixel (∞ where none).
    #[inline]
    pub fn line_at(&self, x: usize, y: usize) -> f64 {
        self.line_depth
            .as_ref()
            .map_or(f64::INFINITY, |d| d[y * self.width + x])
    }
}
