//! Loading benchmarks: reading BINARY and ASCII HyperMesh files and Gmsh 4.1 ASCII files of
//! generated jittered boxes, and building the face adjacency, at 20k, 150k and 1M tetrahedra.
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
    msh: Vec<PathBuf>,
}

/// The box as Gmsh writes a 4.1 ASCII file: one node block, one element block, a row a line.
fn write_msh(vol: &vorang::Volume, path: &std::path::Path) {
    use std::fmt::Write as _;
    let (nodes, tets) = (vol.mesh.nodes(), vol.mesh.tets());
    let (n, m) = (nodes.len(), tets.len());
    let mut t = format!("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {n} 1 {n}\n3 1 0 {n}\n");
    for i in 1..=n {
        writeln!(t, "{i}").unwrap();
    }
    for p in nodes {
        writeln!(t, "{} {} {}", p[0], p[1], p[2]).unwrap();
    }
    write!(t, "$EndNodes\n$Elements\n1 {m} 1 {m}\n3 1 4 {m}\n").unwrap();
    for (i, c) in tets.iter().enumerate() {
        writeln!(
            t,
            "{} {} {} {} {}",
            i + 1,
            c[0] + 1,
            c[1] + 1,
            c[2] + 1,
            c[3] + 1
        )
        .unwrap();
    }
    t.push_str("$EndElements\n");
    std::fs::write(path, t).expect("write benchmark file");
}

fn files() -> &'static Files {
    static FILES: OnceLock<Files> = OnceLock::new();
    FILES.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temporary folder");
        let mut binary = Vec::new();
        let mut ascii = Vec::new();
        let mut msh = Vec::new();
        for n in SIZES {
            let vol = jittered_box(n, 0.1, 1);
            let path = dir.path().join(format!("box{n}.msh"));
            write_msh(&vol, &path);
            msh.push(path);
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
            msh,
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

#[divan::bench(args = SIZES, sample_count = 10)]
fn read_msh(bencher: divan::Bencher, n: usize) {
    let path = &files().msh[index(n)];
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
