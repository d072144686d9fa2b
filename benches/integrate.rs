//! Cost of one segment for every integration rule (issue: exact integration), on segments
//! that are optically thin (χ·Δs ≤ 1, the common case inside small cells), mixed (10⁻³ … 10²)
//! and thick (10 … 10³). `cargo bench --bench integrate`.

use divan::counter::ItemsCount;
use vorang::integrate::Segment;
use vorang::mesh::generate::SplitMix64;

fn main() {
    divan::main();
}

const N: usize = 4096;

/// `smooth`: χ at the two ends differs by at most ±20 % (a smooth field in a small cell);
/// otherwise independent.
fn segments(lo: f64, hi: f64, quadratic: bool, smooth: bool) -> Vec<Segment> {
    let mut rng = SplitMix64(7);
    (0..N)
        .map(|_| {
            let c = 10f64.powf(lo + (hi - lo) * rng.next_f64());
            let a = if smooth {
                c * (0.8 + 0.4 * rng.next_f64())
            } else {
                10f64.powf(lo + (hi - lo) * rng.next_f64())
            };
            let mut eta = || [rng.next_f64(), rng.next_f64(), rng.next_f64()];
            let (far, near, mid) = (eta(), eta(), eta());
            Segment {
                eta: [far, near],
                chi: [a, c],
                ds: 1.0,
                eta_mid: quadratic.then_some(mid),
            }
        })
        .collect()
}

fn run(bencher: divan::Bencher, rule: &str, lo: f64, hi: f64, quadratic: bool, smooth: bool) {
    let info = vorang::integrate::find(rule).expect("rule");
    let segs = segments(lo, hi, quadratic, smooth);
    bencher.counter(ItemsCount::new(N)).bench(|| {
        let mut sum = 0.0;
        for s in &segs {
            let (b, t) = (info.rule)(divan::black_box(s));
            sum += b[0] + t;
        }
        sum
    });
}

const NAMES: [&str; 4] = ["trapez", "constEA", "weightedConstEA", "linear"];

/// Optical depth 10⁻³ … 1 at both ends, independently.
#[divan::bench(args = NAMES)]
fn thin(bencher: divan::Bencher, rule: &str) {
    run(bencher, rule, -3.0, 0.0, false, false);
}

/// Depth 10⁻³ … 10², smooth along the segment: what rendering a smooth field produces.
#[divan::bench(args = NAMES)]
fn smooth(bencher: divan::Bencher, rule: &str) {
    run(bencher, rule, -3.0, 2.0, false, true);
}

/// Depth 10⁻³ … 10² at both ends, independently (the hardest mix for `linear`).
#[divan::bench(args = NAMES)]
fn mixed(bencher: divan::Bencher, rule: &str) {
    run(bencher, rule, -3.0, 2.0, false, false);
}

/// Depth 10 … 10³ at both ends, independently.
#[divan::bench(args = NAMES)]
fn thick(bencher: divan::Bencher, rule: &str) {
    run(bencher, rule, 1.0, 3.0, false, false);
}

/// The linear rule with quadratic emission (ABSORPTION_WEIGHTED), smooth segments.
#[divan::bench]
fn linear_quadratic_smooth(bencher: divan::Bencher) {
    run(bencher, "linear", -3.0, 2.0, true, true);
}
