//! Any byte string given to the collection parsers (`.pvd`, `.pvtu`, `.vtm`, `.series`) must
//! give entries or a located error (file and a line ≥ 1) — never a panic, a hang or an
//! allocation out of proportion to the input. Entries have finite times and non-empty file
//! names; a series built from them has its steps in time order, each with at least one file.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use vorang::formats::collection::{Entry, Kind, Series, pvd, pvtu, series_json, vtm};

fn check(result: Result<Vec<Entry>, vorang::ParseError>, name: &str) {
    match result {
        Ok(entries) => {
            assert!(!entries.is_empty());
            for e in entries {
                assert!(e.time.is_finite());
                assert!(!e.file.trim().is_empty());
                assert!(e.line >= 1);
            }
        }
        Err(e) => {
            assert_eq!(e.file, name);
            assert!(e.line >= 1);
        }
    }
}

fuzz_target!(|data: &[u8]| {
    check(pvd::entries(data, "fuzz.pvd"), "fuzz.pvd");
    check(pvtu::entries(data, "fuzz.pvtu"), "fuzz.pvtu");
    check(
        vtm::leaves(data, "fuzz.vtm").map(|l| l.into_iter().map(|l| l.entry).collect()),
        "fuzz.vtm",
    );
    check(series_json::entries(data, "fuzz.series"), "fuzz.series");
    for kind in [Kind::Pvd, Kind::Pvtu, Kind::Vtm, Kind::SeriesJson] {
        if let Ok(series) = Series::parse(data, Path::new("dir/fuzz"), kind) {
            assert!(!series.is_empty());
            assert!(series.steps.windows(2).all(|w| w[0].time <= w[1].time));
            assert!(series.steps.iter().all(|s| !s.parts.is_empty()));
            let (t0, t1) = series.time_range();
            assert!(series.nearest(t0) <= series.nearest(t1));
        }
    }
});
