//! The kernels against the scalar rule, and every compiled copy against the others and against
//! the pixel-by-pixel path.

use super::buffer::SpanBuffer;
use super::dispatch::{Kernel, draw_fan_with, draw_with, supported};
use super::integrand::{Clip, SpanCell, SpanPieces};
use super::shade::shade;
use crate::integrate::Segment;
use crate::integrate::linear::rule;
use crate::integrate::linear_lanes::terms_for;
use crate::render::composite::{Order, composite};
use crate::render::faces::CellFaces;
use crate::render::gouraud::{self, Fan};
use crate::render::raster::Rect;

fn cell() -> SpanCell {
    SpanCell {
        q: [
            [0.2, 0.01, -0.003, 0.05, 0.0, 0.0],
            [0.5, -0.002, 0.004, 0.1, 0.0, 0.0],
            [0.9, 0.0, 0.0, -0.02, 0.0, 0.0],
            [0.3, 0.001, 0.002, 0.4, 0.0, 0.0],
        ],
        rays: None,
        clip: None,
        terms: terms_for(0.45, 0.2).unwrap(),
        brightness: 1.5,
    }
}

fn buffer(n: usize) -> SpanBuffer {
    let mut buf = SpanBuffer::default();
    for i in 0..n {
        let (x, y) = (3.5 + i as f64, 7.5 - 0.5 * i as f64);
        let near = 0.1 + 0.01 * i as f64;
        buf.push(i, x, y, near, near + 0.05 * (i % 7) as f64);
    }
    buf
}

#[test]
fn the_kernel_matches_the_scalar_rule() {
    let c = cell();
    let mut buf = buffer(21);
    shade(&c, &mut buf);
    assert_eq!(buf.len(), 21);
    for i in 0..21 {
        let (x, y, near, far) = (buf.x[i], buf.y[i], buf.near[i], buf.far[i]);
        let v = |k: usize, t: f64| c.q[k][0] + c.q[k][1] * x + c.q[k][2] * y + c.q[k][3] * t;
        let seg = Segment {
            eta: [
                [v(0, far), v(1, far), v(2, far)],
                [v(0, near), v(1, near), v(2, near)],
            ],
            chi: [v(3, far), v(3, near)],
            ds: far - near,
            eta_mid: None,
        };
        let (b, theta) = rule(&seg);
        for ch in 0..3 {
            let want = b[ch] * c.brightness;
            assert!(
                (buf.b[ch][i] - want).abs() <= 1e-15 * (1.0 + want.abs()),
                "{i}"
            );
        }
        assert!((buf.theta[i] - theta).abs() <= 1e-15, "{i}");
    }
}

/// The whole draw (gathering, the kernel in batches of 8, 16 or 32 lanes, compositing)
/// compiled for each kernel, for one piece and for a cell cut into two pieces by a clip: the
/// kernels with fused multiply-adds (AVX2, AVX-512) give the same bits, the baseline (a
/// product and a sum, rounded twice) the same values to rounding.
#[test]
fn every_compiled_draw_gives_the_same_bits() {
    use crate::predicates::entry_sign;
    let screen = [[3.2, 4.1], [40.7, 9.3], [20.2, 37.9], [18.4, 15.6]];
    let depth = [1.0, 1.3, 0.8, 2.1];
    let faces = CellFaces::new([0, 1, 2, 3], &screen, &depth, entry_sign(false), false);
    let hull = &screen[..3];
    let rect = Rect {
        x0: 2,
        y0: 3,
        x1: 45,
        y1: 41,
    };
    let one = SpanPieces::one(cell());
    let mut two = SpanPieces::one(cell());
    let clip = |lo, hi| {
        Some(Clip {
            s: [0.0, 0.01, 0.0, 1.0, 0.0, 0.0],
            lo,
            hi,
        })
    };
    two.cells[0].clip = clip(f64::NEG_INFINITY, 1.2);
    two.cells[1].clip = clip(1.2, f64::INFINITY);
    two.count = 2;
    #[cfg(target_arch = "x86_64")]
    let kinds = [Kernel::Baseline, Kernel::Avx2, Kernel::Avx512];
    #[cfg(not(target_arch = "x86_64"))]
    let kinds = [Kernel::Baseline];
    for pieces in [&one, &two] {
        let (mut fused, mut baseline) = (None, None);
        for k in kinds.into_iter().filter(|&k| supported(k)) {
            let n = (rect.x1 - rect.x0) * (rect.y1 - rect.y0);
            let mut acc = vec![([0.1, 0.2, 0.3], 1.0); n];
            let mut buf = SpanBuffer::default();
            let drawn = draw_with(
                k,
                pieces,
                &screen,
                hull,
                &faces,
                rect,
                &mut buf,
                Some(&mut acc),
                Order::BackToFront,
            );
            assert!(drawn > 300, "{drawn}");
            let values: Vec<f64> = acc
                .iter()
                .flat_map(|(c, t)| [c[0], c[1], c[2], *t])
                .collect();
            if k == Kernel::Baseline {
                baseline = Some(values);
                continue;
            }
            let bits: Vec<u64> = values.iter().map(|v| v.to_bits()).collect();
            match &fused {
                None => fused = Some((bits, values)),
                Some((r, _)) => assert!(r == &bits, "{k:?}"),
            }
        }
        if let (Some(b), Some((_, f))) = (&baseline, &fused) {
            let most = b
                .iter()
                .zip(f)
                .map(|(b, f)| (b - f).abs())
                .fold(0.0, f64::max);
            assert!(most < 1e-14, "{most}");
        }
    }
}

/// The Gouraud fan drawn in lanes by each compiled kernel: the same bits as pixel by pixel.
#[test]
fn every_compiled_fan_draw_matches_the_pixels() {
    use crate::render::footprint::footprint;
    use crate::render::raster::rasterize_convex;
    use crate::scene::{Camera, Projector};
    let proj = Projector::new(
        Some(&Camera::Ortho {
            left: 0.0,
            right: 40.0,
            bottom: 0.0,
            top: 40.0,
            front: -10.0,
            back: 10.0,
        }),
        [1.0; 3],
        40,
        40,
    )
    .unwrap();
    // Cells of every class with a fan (1: the fourth node inside, 2: crossing edges,
    // 3: a node over an edge, 4: two nodes on one spot; fewer than four sectors leave
    // unused ones that must never win), then random cells with random values.
    let mut cells = vec![
        [
            [3.0, 3.0, 0.0],
            [36.0, 35.0, 0.0],
            [34.0, 4.0, 2.0],
            [5.0, 33.0, 2.5],
        ],
        [
            [2.0, 3.0, 0.0],
            [35.0, 5.0, 0.5],
            [15.0, 37.0, 1.0],
            [16.0, 14.0, 3.0],
        ],
        [
            [3.0, 3.0, 0.0],
            [35.0, 3.0, 0.0],
            [19.0, 36.0, 1.0],
            [19.0, 3.0, 4.0],
        ],
        [
            [3.0, 3.0, 0.0],
            [35.0, 6.0, 0.0],
            [19.0, 36.0, 1.0],
            [3.0, 3.0, 4.0],
        ],
    ];
    let mut rng = crate::mesh::generate::SplitMix64(0x2545_f491_4f6c_dd1d);
    let mut next = move || rng.next_f64();
    for _ in 0..300 {
        cells.push(std::array::from_fn(|_| {
            [next() * 44.0 - 2.0, next() * 44.0 - 2.0, next() * 8.0 - 4.0]
        }));
    }
    let mut values = [
        [0.9, 0.2, 0.0, 0.5],
        [0.8, 0.9, 0.3, 0.0],
        [1.0, 0.1, 0.8, 0.2],
        [0.7, 0.4, 0.4, 0.9],
        [0.3, 0.6, 0.7, 0.1],
    ];
    let rect = Rect {
        x0: 4,
        y0: 2,
        x1: 38,
        y1: 39,
    };
    let tw = rect.x1 - rect.x0;
    let n = tw * (rect.y1 - rect.y0);
    let start = vec![([0.1, 0.2, 0.3], 1.0); n];
    let mut classes = std::collections::HashSet::new();
    let mut pixels = 0;
    for (c, eye) in cells.iter().enumerate() {
        if c >= 4 {
            values = std::array::from_fn(|_| std::array::from_fn(|_| next()));
        }
        let screen = eye.map(|p| proj.screen(p));
        let Some(fp) = footprint([0, 1, 2, 3], eye, &screen, &proj) else {
            continue;
        };
        let (Some(fan), Some((v, count))) = (Fan::new(&fp, &values), fp.hull()) else {
            continue;
        };
        classes.insert(fp.projection.unwrap().class);
        let mut want = start.clone();
        rasterize_convex(&v[..count], rect, |x, y| {
            let px = gouraud::shade(1.5, fan.at(x as f64 + 0.5, y as f64 + 0.5));
            composite(
                Order::BackToFront,
                &mut want[(y - rect.y0) * tw + x - rect.x0],
                px,
            );
            pixels += 1;
        });
        #[cfg(target_arch = "x86_64")]
        let kinds = [Kernel::Baseline, Kernel::Avx2, Kernel::Avx512];
        #[cfg(not(target_arch = "x86_64"))]
        let kinds = [Kernel::Baseline];
        for k in kinds.into_iter().filter(|&k| supported(k)) {
            let mut acc = start.clone();
            let mut buf = SpanBuffer::default();
            draw_fan_with(
                k,
                &fan,
                1.5,
                &screen,
                &v[..count],
                rect,
                &mut buf,
                &mut acc,
                Order::BackToFront,
            );
            for (a, b) in acc.iter().zip(&want) {
                assert_eq!(a.1.to_bits(), b.1.to_bits(), "{k:?} cell {c}");
                for ch in 0..3 {
                    assert_eq!(a.0[ch].to_bits(), b.0[ch].to_bits(), "{k:?} cell {c}");
                }
            }
        }
    }
    assert!(
        classes.len() >= 4 && pixels > 10_000,
        "{classes:?} {pixels}"
    );
}
