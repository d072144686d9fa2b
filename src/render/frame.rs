//! What every tile of one frame shares: the volume and mapping, the camera, node positions in
//! eye space and on screen, and per-pixel inputs (background, line depth).

use crate::mapping::Mapping;
use crate::scene::Projector;
use crate::volume::Volume;

pub struct Frame<'a> {
    pub vol: &'a Volume,
    pub mapping: &'a Mapping,
    pub projector: Projector,
    pub width: usize,
    pub height: usize,
    /// Node positions in eye space.
    pub eye_nodes: Vec<[f64; 3]>,
    /// Node positions on screen (meaningless for perspective nodes before the near plane).
    pub screen: Vec<[f64; 2]>,
    /// Background intensity I0 per pixel.
    pub background: Vec<[f64; 3]>,
    /// Depth of the nearest grid line per pixel (∞ where none).
    pub line_depth: Vec<f64>,
}

impl Frame<'_> {
    /// η and χ at the point with barycentric coordinates `lambda` in `cell`: every needed field
    /// evaluated once with its own interpolator, then mapped. `buf` is scratch space.
    #[inline]
    pub fn mapped(&self, cell: usize, lambda: &[f64; 4], buf: &mut Vec<f64>) -> ([f64; 3], f64) {
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

    /// The four corners of a cell in eye space.
    #[inline]
    pub fn eye_corners(&self, cell: usize) -> [[f64; 3]; 4] {
        self.vol.mesh.tets()[cell].map(|n| self.eye_nodes[n as usize])
    }

    #[inline]
    pub fn screen_corners(&self, cell: usize) -> [[f64; 2]; 4] {
        self.vol.mesh.tets()[cell].map(|n| self.screen[n as usize])
    }
}
