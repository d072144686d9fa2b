//! Loading benchmarks (issue: foundation): reading BINARY and ASCII HyperMesh files of generated
//! jittered boxes, and building the face adjacency, at 20k, 150k and 1M tetrahedra.
//!
//! Run: `cargo bench --bench hypermesh`. The files are generated into a temporary folder once.

use std::path::PathBuf;
use std::sync::OnceLock;

use vorang::hypermesh::{self, Encoding, Layout, WriteOptions};
use vorang::mesh::TetMesh;
use vorang::volume::jittered_box;

const SIZES: [usize; 3] = [20_000, 150_000, 1_000_000];

fn main() {
    divan::main();
}

struct Files {
    _dir: tempfile::TempDir,
    binary: Vec<PathBuf>,
    ascii: Vec<PathBuf>,
}

fn files() -> &'static Files {
    static FILES: OnceLock<Files> = OnceLock::new();
    FILES.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temporary folder");
        let mut binary = Vec::new();
        let mut ascii = Vec::new();
        for n in SIZES {
            let vol = jittered_box(n, 0.1, 1);
            for (enc, list, ext) in [
                (Encoding::Binary, &mut binary, "bin"),
                (Encoding::Ascii, &mut ascii, "hmesh"),
            ] {
                let path = dir.path().join(format!("box{n}.{ext}"));
                let opts = WriteOptions {
                    encoding: enc,
                    layout: Layout::Small,
                };
                hypermesh::save_volume(&vol, &path, opts).expect("write benchmark file");
                list.push(path);
            }
        }
        Files {
            _dir: dir,
            binary,
            ascii,
        }
    })
}

fn index(n: usize) -> usize {
    SIZES.iter().position(|&s| s == n).unwrap_or(0)
}

#[divan::bench(args = SIZES, sample_count = 10)]
fn read_binary(bencher: divan::Bencher, n: usize) {
    let path = &files().binary[index(n)];
    bencher.bench(|| vorang::Volume::load(path).expect("read"));
}

#[divan::bench(args = SIZES, sample_count = 10)]
fn read_ascii(bencher: divan::Bencher, n: usize) {
    let path = &files().ascii[index(n)];
    bencher.bench(|| vorang::Volume::load(path).expect("read"));
}

/// Validation, orientation and face adjacency of an already generated cell list.
#[divan::bench(args = SIZES, sample_count = 10)]
fn build_mesh(bencher: divan::Bencher, n: usize) {
    let cubes = vorang::mesh::generate::cubes_for(n);
    let (nodes, tets) = vorang::mesh::generate::kuhn_box([cubes; 3], [1.0; 3], 0.1, 1);
    bencher
        .with_inputs(|| (nodes.clone(), tets.clone()))
        .bench_values(|(nodes, tets)| TetMesh::new(nodes, tets).expect("valid"));
}
