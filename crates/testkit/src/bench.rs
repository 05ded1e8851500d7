//! Inputs shared by the root benches (`use testkit::bench as common;` in `benches/*.rs`)
//! and by `examples/bench_cache.rs`: the shared real meshes, and large
//! meshes made from them with `halfedge::generators::subdivide` (1-to-4), generated once
//! into `bench-cache/` at the workspace root (git-ignored) as binary little-endian PLY and
//! read back on later runs.
//!
//! A cached file is used when it is newer than its source mesh; otherwise it is generated
//! again (written to a temporary file and renamed, so that an interrupted run or two
//! benches at once never leave a truncated file). `MULTIRES_MESHES` overrides the shared
//! meshes folder, `MULTIRES_BENCH_CACHE` the cache folder.
//!
//! Prepare the cache ahead (with progress bars):
//!
//! ```text
//! cargo run --release --example bench_cache            # every size
//! cargo run --release --example bench_cache -- 1M 2M   # some sizes
//! ```

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use std::time::SystemTime;

use halfedge::io::{self, PlyFormat};
use halfedge::{generators, Mesh};

// The shared meshes, found as the integration tests find them (`MULTIRES_MESHES`, else
// `shared/meshes` above the workspace).
pub use crate::{load_shared, shared_meshes as meshes_dir};

/// The cache folder: `MULTIRES_BENCH_CACHE`, else `bench-cache/` at the workspace root.
pub fn cache_dir() -> PathBuf {
    std::env::var_os("MULTIRES_BENCH_CACHE")
        .map(PathBuf::from)
        .unwrap_or_else(|| crate::workspace_root().join("bench-cache"))
}

/// A large bench input: a shared mesh subdivided 1-to-4 a number of times.
#[derive(Clone, Copy, Debug)]
pub struct Large {
    /// Short label used in bench names (`"1M"`).
    pub label: &'static str,
    /// The shared mesh it is made from.
    pub source: &'static str,
    /// Number of 1-to-4 subdivisions.
    pub subdivisions: usize,
    /// Faces of the result (the source's faces × 4^subdivisions).
    pub faces: usize,
}

/// Stanford bunny ×2: 1.1 M faces.
pub const BUNNY_X2: Large = Large {
    label: "1M",
    source: "stanford-bunny.obj",
    subdivisions: 2,
    faces: 1_111_216,
};
/// Nefertiti ×2: 1.6 M faces, 0.8 M vertices (the workspace's usual big mesh).
pub const NEFERTITI_X2: Large = Large {
    label: "2M",
    source: "nefertiti.obj",
    subdivisions: 2,
    faces: 1_599_008,
};
/// Stanford bunny ×3: 4.4 M faces.
pub const BUNNY_X3: Large = Large {
    label: "4M",
    source: "stanford-bunny.obj",
    subdivisions: 3,
    faces: 4_444_864,
};
/// Horse ×3: 6.2 M faces.
pub const HORSE_X3: Large = Large {
    label: "6M",
    source: "horse.ply",
    subdivisions: 3,
    faces: 6_205_824,
};

/// Stanford bunny ×4: 17.8 M faces, 8.9 M vertices (the 10⁷-face input).
pub const BUNNY_X4: Large = Large {
    label: "18M",
    source: "stanford-bunny.obj",
    subdivisions: 4,
    faces: 17_779_456,
};

/// Fandisk ×6: 53 M faces, 26.5 M vertices (the 50 M-face workflow run of issue 32; made
/// only when asked for by name: its binary PLY takes 1.3 GB).
pub const FANDISK_X6: Large = Large {
    label: "50M",
    source: "fandisk.obj",
    subdivisions: 6,
    faces: 53_026_816,
};

/// The large inputs, smallest first: about 1, 2, 4, 6 and 18 million faces.
pub const LARGE: [Large; 5] = [BUNNY_X2, NEFERTITI_X2, BUNNY_X3, HORSE_X3, BUNNY_X4];

/// Every input [`select`] knows: [`LARGE`], then the ones made only when named.
pub const KNOWN: [Large; 6] = [
    BUNNY_X2,
    NEFERTITI_X2,
    BUNNY_X3,
    HORSE_X3,
    BUNNY_X4,
    FANDISK_X6,
];

/// The inputs whose labels are listed (case-insensitive), in [`KNOWN`]'s order, or
/// [`LARGE`] when none is; unknown labels are an error naming the known ones.
pub fn select(labels: &[String]) -> Result<Vec<Large>, String> {
    if labels.is_empty() {
        return Ok(LARGE.to_vec());
    }
    for l in labels {
        if !KNOWN.iter().any(|m| m.label.eq_ignore_ascii_case(l)) {
            let known: Vec<&str> = KNOWN.iter().map(|m| m.label).collect();
            return Err(format!("unknown size {l:?}; known: {known:?}"));
        }
    }
    Ok(KNOWN
        .into_iter()
        .filter(|m| labels.iter().any(|l| m.label.eq_ignore_ascii_case(l)))
        .collect())
}

/// A step of [`Large::prepare`], for progress reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Reading the source mesh.
    Reading,
    /// Subdividing: `done` of `total` subdivisions finished, `faces` so far.
    Subdividing {
        /// Subdivisions finished.
        done: usize,
        /// Subdivisions in all.
        total: usize,
        /// Faces after the last finished subdivision.
        faces: usize,
    },
    /// Writing the binary PLY.
    Writing,
    /// The cached file is up to date (nothing generated).
    Cached,
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

impl Large {
    /// Display name, e.g. `"nefertiti ×2 (1,599,008 faces)"`.
    pub fn name(&self) -> String {
        let stem = self.source.split('.').next().unwrap_or(self.source);
        format!(
            "{stem} ×{} ({} faces)",
            self.subdivisions,
            thousands(self.faces)
        )
    }

    /// The cached PLY: `bench-cache/<stem>-subdivided-<k>.ply`.
    pub fn path(&self) -> PathBuf {
        let stem = self.source.split('.').next().unwrap_or(self.source);
        cache_dir().join(format!("{stem}-subdivided-{}.ply", self.subdivisions))
    }

    /// The source mesh in the shared folder.
    pub fn source_path(&self) -> PathBuf {
        meshes_dir().join(self.source)
    }

    /// True when the cached file exists and is newer than its source mesh.
    pub fn is_fresh(&self) -> bool {
        match (modified(&self.path()), modified(&self.source_path())) {
            (Some(cached), Some(source)) => cached >= source,
            _ => false,
        }
    }

    /// Generates the cached PLY unless it is fresh, reporting each step; returns its path.
    pub fn prepare(&self, progress: &mut dyn FnMut(Step)) -> PathBuf {
        let path = self.path();
        if self.is_fresh() {
            progress(Step::Cached);
            return path;
        }
        progress(Step::Reading);
        let mut mesh = load_shared(self.source);
        for done in 1..=self.subdivisions {
            mesh = generators::subdivide(&mesh);
            progress(Step::Subdividing {
                done,
                total: self.subdivisions,
                faces: mesh.n_faces(),
            });
        }
        assert_eq!(
            mesh.n_faces(),
            self.faces,
            "{}: unexpected face count",
            self.name()
        );
        progress(Step::Writing);
        let dir = cache_dir();
        std::fs::create_dir_all(&dir)
            .unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
        let partial = path.with_extension(format!("ply.partial-{}", std::process::id()));
        io::write_ply(&partial, &mesh, PlyFormat::BinaryLittleEndian)
            .unwrap_or_else(|e| panic!("{e}"));
        std::fs::rename(&partial, &path)
            .unwrap_or_else(|e| panic!("cannot rename {}: {e}", partial.display()));
        path
    }

    /// The cached PLY's path, generating it first if needed (silently).
    pub fn cached(&self) -> PathBuf {
        self.prepare(&mut |_| {})
    }

    /// The mesh, read from the cache (generated first if needed).
    pub fn load(&self) -> Mesh {
        let path = self.cached();
        let mesh = io::read(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .0;
        assert_eq!(
            mesh.n_faces(),
            self.faces,
            "{}: stale cache?",
            path.display()
        );
        mesh
    }
}

/// Nefertiti subdivided twice (0.8 M vertices, 1.6 M faces), from the cache.
pub fn nefertiti_x2() -> Mesh {
    NEFERTITI_X2.load()
}

/// `1234567` → `"1,234,567"`.
pub fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Sum of the neighbour indices of every vertex (so that the circulation cannot be
/// optimised away), in parallel over vertex slots: the one-ring circulation bench.
pub fn one_ring_sum_parallel(mesh: &Mesh) -> usize {
    (0..mesh.vertex_slots())
        .into_par_iter()
        .filter_map(|i| mesh.vertex_at(i))
        .map(|v| {
            mesh.adjacent_vertices(v)
                .map(|w| mesh.vertex_index(w))
                .sum::<usize>()
        })
        .sum()
}
