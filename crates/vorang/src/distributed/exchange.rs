//! The messages of a distributed frame (docs/distributed.md, "Compositing"): direct send.
//!
//! The image's [`DEEP_TILE`](crate::render::deep::DEEP_TILE) tiles are dealt to the ranks in turn ([`owner`]). Every rank sends
//! the owner of each tile its runs there, all in one all-to-all ([`pack`]); the owner sorts each
//! pixel's runs by depth — equal depths in rank order, as the runs arrive concatenated by
//! sending rank — and composites them as one process would ([`settle`], [`Resolver::pixel`]);
//! rank 0 gathers the owned tiles into the image ([`assemble`]). Nothing depends on the order
//! in which messages arrive, nor on threads.
//!
//! Per tile a message holds the number of runs (`u32`), then — unless that is 0 — the number
//! per pixel (`u32`, row by row) and the runs (`near, far, b₀, b₁, b₂, θ` as `f64`), all
//! little-endian.

use rayon::prelude::*;

use crate::error::Error;
use crate::framebuffer::Framebuffer;
use crate::render::deep::{DeepTile, Resolver, deep_rect, deep_tiles};
use crate::render::runs::Stretch;

/// The rank that owns tile `tile`'s pixels.
pub fn owner(tile: usize, ranks: usize) -> usize {
    tile % ranks.max(1)
}

/// Bytes of one run in a message.
const STRETCH_BYTES: usize = 48;

/// This rank's runs, per tile, as the message to each rank (the tiles it owns, in order). Each
/// tile is freed once it is packed, so that the runs are not held twice.
pub fn pack(tiles: Vec<DeepTile>, ranks: usize) -> Vec<Vec<u8>> {
    // Sized exactly first: grown by doubling, the buffers could hold twice the runs.
    let mut sizes = vec![0usize; ranks];
    for (t, tile) in tiles.iter().enumerate() {
        sizes[owner(t, ranks)] += 4 + match tile.stretches.len() {
            0 => 0,
            n => 4 * tile.counts.len() + STRETCH_BYTES * n,
        };
    }
    let mut out: Vec<Vec<u8>> = sizes.into_iter().map(Vec::with_capacity).collect();
    for (t, tile) in tiles.into_iter().enumerate() {
        let buf = &mut out[owner(t, ranks)];
        buf.extend_from_slice(&(tile.stretches.len() as u32).to_le_bytes());
        if tile.stretches.is_empty() {
            continue;
        }
        for c in &tile.counts {
            buf.extend_from_slice(&c.to_le_bytes());
        }
        for s in &tile.stretches {
            for v in [s.near, s.far, s.b[0], s.b[1], s.b[2], s.theta] {
                buf.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    out
}

/// Reads little-endian numbers from a message, checking its length.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], Error> {
        let out = self
            .bytes
            .get(self.at..self.at + n)
            .ok_or_else(|| Error::Invalid("a distributed frame's message is cut short".into()))?;
        self.at += n;
        Ok(out)
    }

    fn u32(&mut self) -> Result<u32, Error> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self) -> Result<u64, Error> {
        let mut a = [0; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(a))
    }
}

fn f64_at(b: &[u8], i: usize) -> f64 {
    let mut a = [0; 8];
    a.copy_from_slice(&b[8 * i..8 * i + 8]);
    f64::from_le_bytes(a)
}

/// One sender's part of one owned tile: its counts per pixel and its runs, as bytes.
#[derive(Clone, Copy, Default)]
struct Part<'a> {
    counts: &'a [u8],
    runs: &'a [u8],
}

/// What an owner settled: its tiles' pixels, and what the pixels showed.
struct Settled {
    pixels: Vec<[f32; 4]>,
    overlap_pixels: u64,
    most: u64,
    /// Pixels where one process may have stopped compositing front to back early
    /// (`render_ftb`; [`Resolver::stops_early`]).
    opaque_pixels: u64,
}

/// The owner's step: from the messages of every rank (by sending rank), this rank's tiles
/// settled pixel by pixel ([`Resolver::pixel`]), as the message to rank 0: the pixels with
/// an overlap, the most runs one pixel held and the pixels that turned opaque front to back
/// (`u64` each), then the tiles' pixels (`f32` RGBA, tile by tile, row by row).
pub fn settle(
    incoming: &[&[u8]],
    rank: usize,
    ranks: usize,
    (width, height): (usize, usize),
    resolver: &Resolver,
) -> Result<Vec<u8>, Error> {
    let (tx, ty) = deep_tiles(width, height);
    let owned: Vec<usize> = (0..tx * ty).filter(|&t| owner(t, ranks) == rank).collect();
    // Where each sender's part of each owned tile lies in its message.
    let mut parts = vec![vec![Part::default(); incoming.len()]; owned.len()];
    for (s, bytes) in incoming.iter().enumerate() {
        let mut r = Reader { bytes, at: 0 };
        for (k, &t) in owned.iter().enumerate() {
            let total = r.u32()? as usize;
            if total == 0 {
                continue;
            }
            let rect = deep_rect(t, width, height);
            let n = (rect.x1 - rect.x0) * (rect.y1 - rect.y0);
            parts[k][s] = Part {
                counts: r.take(4 * n)?,
                runs: r.take(STRETCH_BYTES * total)?,
            };
        }
        if r.at != bytes.len() {
            return Err(Error::Invalid(
                "a distributed frame's message is longer than its tiles".into(),
            ));
        }
    }
    let settled: Vec<Settled> = owned
        .par_iter()
        .zip(&parts)
        .map(|(&t, parts)| settle_tile(deep_rect(t, width, height), parts, resolver))
        .collect();
    let overlap_pixels = settled.iter().map(|s| s.overlap_pixels).sum::<u64>();
    let most = settled.iter().map(|s| s.most).max().unwrap_or(0);
    let opaque_pixels = settled.iter().map(|s| s.opaque_pixels).sum::<u64>();
    let n: usize = settled.iter().map(|s| s.pixels.len()).sum();
    let mut out = Vec::with_capacity(24 + 16 * n);
    out.extend_from_slice(&overlap_pixels.to_le_bytes());
    out.extend_from_slice(&most.to_le_bytes());
    out.extend_from_slice(&opaque_pixels.to_le_bytes());
    for s in &settled {
        for p in &s.pixels {
            for v in p {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    Ok(out)
}

/// One owned tile: per pixel the runs of every sender, in sender order, settled.
fn settle_tile(rect: crate::render::Rect, parts: &[Part], resolver: &Resolver) -> Settled {
    let n = (rect.x1 - rect.x0) * (rect.y1 - rect.y0);
    // Per sender: where its runs for the next pixel start.
    let mut next = vec![0usize; parts.len()];
    let mut runs: Vec<(Stretch, u32)> = Vec::new();
    let mut out = Settled {
        pixels: Vec::with_capacity(n),
        overlap_pixels: 0,
        most: 0,
        opaque_pixels: 0,
    };
    let w = rect.x1 - rect.x0;
    for slot in 0..n {
        runs.clear();
        for (s, part) in parts.iter().enumerate() {
            if part.counts.is_empty() {
                continue;
            }
            let c = &part.counts[4 * slot..4 * slot + 4];
            let count = u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize;
            for i in next[s]..next[s] + count {
                let b = &part.runs[STRETCH_BYTES * i..STRETCH_BYTES * (i + 1)];
                let run = Stretch {
                    near: f64_at(b, 0),
                    far: f64_at(b, 1),
                    b: [f64_at(b, 2), f64_at(b, 3), f64_at(b, 4)],
                    theta: f64_at(b, 5),
                };
                runs.push((run, s as u32));
            }
            next[s] += count;
        }
        out.most = out.most.max(runs.len() as u64);
        let (x, y) = (rect.x0 + slot % w, rect.y0 + slot / w);
        let (px, overlapped, early) = resolver.pixel(x, y, &mut runs);
        out.overlap_pixels += u64::from(overlapped);
        out.opaque_pixels += u64::from(early);
        out.pixels.push(px);
    }
    out
}

/// Rank 0's step: the image from every owner's message (by rank), the pixels with an
/// overlap, the most runs one pixel held and the pixels that turned opaque front to back.
pub fn assemble(
    gathered: &[Vec<u8>],
    (width, height): (usize, usize),
) -> Result<(Framebuffer, [u64; 3]), Error> {
    let ranks = gathered.len();
    let (tx, ty) = deep_tiles(width, height);
    let mut fb = Framebuffer::try_new(width, height)?;
    let (mut overlaps, mut most, mut opaque) = (0, 0, 0);
    for (rank, bytes) in gathered.iter().enumerate() {
        let mut r = Reader { bytes, at: 0 };
        overlaps += r.u64()?;
        most = most.max(r.u64()?);
        opaque += r.u64()?;
        for t in (0..tx * ty).filter(|&t| owner(t, ranks) == rank) {
            let rect = deep_rect(t, width, height);
            for y in rect.y0..rect.y1 {
                for x in rect.x0..rect.x1 {
                    let b = r.take(16)?;
                    let v = |i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
                    fb.pixels[y * width + x] = [v(0), v(4), v(8), v(12)];
                }
            }
        }
    }
    Ok((fb, [overlaps, most, opaque]))
}
