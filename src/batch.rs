//! Corpus batches: a recipe (or the workflow) mapped over many meshes — a folder, glob
//! patterns or a manifest file — in parallel on one machine, sharded across machines with
//! no coordinator, resumable, with one JSON line per mesh in `report.jsonl` and a
//! `summary.json`. One bad mesh never stops a batch: its line says `error` and why.
//!
//! - **Inputs** ([`collect_inputs`]): a folder is searched recursively for mesh files
//!   (`.obj .ply .off .stl` and their `.gz`); a pattern with `*`, `?` or `[` is a glob; a
//!   `.txt`, `.list` or `.lst` file is a manifest (one path per line, relative to the
//!   manifest's folder, `#` comments); anything else is a mesh file. The list is sorted
//!   and deduplicated, so every machine sees the same corpus in the same order.
//! - **Shards** ([`shard`]): `I/N` takes the meshes whose path hash (FNV-1a of the path
//!   relative to its input root) is `I − 1` modulo `N`: a file always lands on the same
//!   machine, whatever else the corpus holds.
//! - **Outputs**: `OUT/<relative path>-edited.<format>`, mirroring the input folders, with
//!   a sidecar `…-edited.<format>.json` recording the input's and the job's hashes.
//! - **Resuming**: a mesh whose output and sidecar exist, with the same input hash, job
//!   hash and output hash (BLAKE3), is `skipped`; everything else runs again (a changed
//!   input or recipe, an output lost or cut short). An interrupted batch resumes where it
//!   stopped.
//! - **Report**: every mesh appends one line to `OUT/report.jsonl` as it finishes (`input`,
//!   `output`, `status` — `ok`, `skipped` or `error` —, `seconds`, `faces`, `vertices`,
//!   `error`, `input_hash`, `shard`), and the batch writes `OUT/summary.json` at the end.

use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions};
use serde::{Deserialize, Serialize};

use crate::error::{io_error, Error, Result};
use crate::load::{self, Weld};
use crate::progress::{Progress, Silent};
use crate::recipe::{self, Recipe, RecipeError};
use crate::workflow::{self, WorkflowOptions};

/// The extensions of the mesh files a folder is searched for.
pub const MESH_EXTENSIONS: [&str; 8] = [
    ".obj", ".ply", ".off", ".stl", ".obj.gz", ".ply.gz", ".off.gz", ".stl.gz",
];

/// One mesh of a batch: its file and its path relative to the input it came from (which
/// names its output and its shard).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Input {
    /// The file.
    pub path: PathBuf,
    /// Its path relative to its folder, glob root or manifest (the file name for a file
    /// given directly).
    pub relative: PathBuf,
}

/// True when `name` ends with a mesh extension.
#[must_use]
pub fn is_mesh_file(name: &str) -> bool {
    let name = name.to_ascii_lowercase();
    MESH_EXTENSIONS.iter().any(|e| name.ends_with(e))
}

fn walk(root: &Path, dir: &Path, out: &mut Vec<Input>) -> Result<()> {
    let entries = std::fs::read_dir(dir).map_err(io_error(dir))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            walk(root, &path, out)?;
        } else if path
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(is_mesh_file)
        {
            let relative = path.strip_prefix(root).unwrap_or(&path).to_owned();
            out.push(Input { path, relative });
        }
    }
    Ok(())
}

/// The meshes named by `inputs` (folders, globs, manifests, files; see the
/// [module docs](self)), sorted and deduplicated.
///
/// # Errors
/// [`Error::Io`] for a folder or manifest that cannot be read, or a file that does not
/// exist; [`Error::InvalidOption`] for a malformed glob pattern.
pub fn collect_inputs(inputs: &[impl AsRef<str>]) -> Result<Vec<Input>> {
    let mut found = Vec::new();
    for input in inputs {
        let input = input.as_ref();
        let path = Path::new(input);
        if path.is_dir() {
            walk(path, path, &mut found)?;
        } else if input.contains(['*', '?', '[']) && !path.exists() {
            let root = glob_root(input);
            let entries = glob::glob(input).map_err(|e| Error::InvalidOption {
                option: "INPUTS",
                reason: format!("{input:?} is not a glob pattern: {e}"),
            })?;
            let before = found.len();
            for entry in entries {
                let path = entry.map_err(|e| Error::Io {
                    path: e.path().to_owned(),
                    source: std::io::Error::other(e.to_string()),
                })?;
                if path.is_file() {
                    let relative = within(path.strip_prefix(&root).unwrap_or(&path));
                    found.push(Input { path, relative });
                }
            }
            if found.len() == before {
                return Err(Error::InvalidOption {
                    option: "INPUTS",
                    reason: format!("the pattern {input:?} matches no file"),
                });
            }
        } else if is_manifest(input) {
            let text = std::fs::read_to_string(path).map_err(io_error(path))?;
            let base = path.parent().unwrap_or(Path::new(""));
            for line in text.lines() {
                let line = line.split('#').next().unwrap_or("").trim();
                if line.is_empty() {
                    continue;
                }
                let file = base.join(line);
                if !file.is_file() {
                    return Err(Error::Io {
                        path: file,
                        source: std::io::Error::new(
                            std::io::ErrorKind::NotFound,
                            format!("named in the manifest {}", path.display()),
                        ),
                    });
                }
                let relative = within(Path::new(line));
                found.push(Input {
                    path: file,
                    relative,
                });
            }
        } else {
            if !path.is_file() {
                return Err(Error::Io {
                    path: path.to_owned(),
                    source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"),
                });
            }
            found.push(Input {
                path: path.to_owned(),
                relative: within(Path::new(path.file_name().unwrap_or(path.as_os_str()))),
            });
        }
    }
    found.sort();
    found.dedup_by(|a, b| a.path == b.path);
    if found.is_empty() {
        return Err(Error::InvalidOption {
            option: "INPUTS",
            reason: format!(
                "no mesh file in {}",
                inputs
                    .iter()
                    .map(|i| format!("{:?}", i.as_ref()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    Ok(found)
}

/// `path` as a path inside the output folder: its plain components only (an absolute
/// path is mirrored under the folder; `..` is dropped) — so that no input, however
/// named, makes a batch write outside its output folder.
fn within(path: &Path) -> PathBuf {
    use std::path::Component;
    let inside: PathBuf = path
        .components()
        .filter_map(|c| match c {
            Component::Normal(part) => Some(part),
            _ => None,
        })
        .collect();
    if inside.as_os_str().is_empty() {
        path.file_name().map_or(inside, PathBuf::from)
    } else {
        inside
    }
}

fn is_manifest(input: &str) -> bool {
    let lower = input.to_ascii_lowercase();
    [".txt", ".list", ".lst"].iter().any(|e| lower.ends_with(e))
}

/// The folder part of a glob pattern before its first wildcard.
fn glob_root(pattern: &str) -> PathBuf {
    let cut = pattern.find(['*', '?', '[']).unwrap_or(pattern.len());
    let head = &pattern[..cut];
    match head.rfind(['/', '\\']) {
        Some(i) => PathBuf::from(&head[..=i]),
        None => PathBuf::new(),
    }
}

/// FNV-1a of a path's text (with `/` separators): the shard a mesh belongs to.
fn path_hash(path: &Path) -> u64 {
    let text = path.to_string_lossy().replace('\\', "/");
    text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Parses `I/N` (1 ≤ I ≤ N).
///
/// # Errors
/// [`Error::InvalidOption`] for anything else.
pub fn parse_shard(s: &str) -> Result<(usize, usize)> {
    let bad = || Error::InvalidOption {
        option: "--shard",
        reason: format!("expected I/N with 1 <= I <= N, got {s:?}"),
    };
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i == 0 || i > n {
        return Err(bad());
    }
    Ok((i, n))
}

/// The meshes of shard `i` of `n` (from 1; see the [module docs](self)).
#[must_use]
pub fn shard(inputs: Vec<Input>, i: usize, n: usize) -> Vec<Input> {
    inputs
        .into_iter()
        .filter(|input| {
            n == 0 || path_hash(&input.relative) % n as u64 == (i as u64).saturating_sub(1)
        })
        .collect()
}

/// What every mesh of a batch is given.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct BatchOptions {
    /// The output folder.
    pub out: PathBuf,
    /// The recipe; `None`: the workflow.
    pub recipe: Option<Recipe>,
    /// The workflow's options (without a recipe).
    pub workflow: WorkflowOptions,
    /// The output mesh format (`ply`, `obj`, `off`, `stl`).
    pub format: String,
    /// Workflow only: picture panels this many pixels wide (0: no pictures).
    pub picture: usize,
    /// Welding after reading.
    pub weld: Weld,
    /// Meshes processed at once (`None`: one per core).
    pub jobs: Option<usize>,
    /// This machine's shard `(I, N)`, recorded in the report.
    pub shard: Option<(usize, usize)>,
}

impl BatchOptions {
    /// The workflow over every mesh into `out`, as PLY, welded `auto`, no pictures.
    #[must_use]
    pub fn new(out: impl Into<PathBuf>) -> Self {
        Self {
            out: out.into(),
            recipe: None,
            workflow: WorkflowOptions::default(),
            format: "ply".to_owned(),
            picture: 0,
            weld: Weld::Auto,
            jobs: None,
            shard: None,
        }
    }
    /// The same options running `recipe` on every mesh.
    #[must_use]
    pub fn with_recipe(mut self, recipe: Recipe) -> Self {
        self.recipe = Some(recipe);
        self
    }
    /// The same options with `jobs` meshes at once.
    #[must_use]
    pub fn with_jobs(mut self, jobs: usize) -> Self {
        self.jobs = Some(jobs);
        self
    }
    /// The same options writing `format`.
    #[must_use]
    pub fn with_format(mut self, format: impl Into<String>) -> Self {
        self.format = format.into();
        self
    }

    /// A hash of what the job does to each mesh (the recipe or the workflow's options, the
    /// format, the welding): an output made by another job is not reused.
    #[must_use]
    pub fn job_hash(&self) -> String {
        let what = match &self.recipe {
            Some(r) => r.to_toml(),
            None => format!("workflow {:?} picture {}", self.workflow, self.picture),
        };
        let text = format!("{what}|{}|{:?}", self.format, self.weld);
        blake3::hash(text.as_bytes()).to_hex().to_string()
    }
}

/// One line of `report.jsonl`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The input file.
    pub input: String,
    /// The output mesh (for an error, where it would have been).
    pub output: String,
    /// `ok`, `skipped` (its output is up to date) or `error`.
    pub status: String,
    /// Seconds spent on it.
    pub seconds: f64,
    /// Faces of the input (0 when it could not be read).
    pub faces: usize,
    /// Vertices of the input (0 when it could not be read).
    pub vertices: usize,
    /// Why it failed (`null` otherwise).
    pub error: Option<String>,
    /// BLAKE3 of the input file's bytes.
    pub input_hash: Option<String>,
    /// `I/N` when the batch ran one shard.
    pub shard: Option<String>,
}

/// The sidecar next to an output: what made it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Sidecar {
    input: String,
    input_hash: String,
    job_hash: String,
    /// The output's own hash: an output changed or cut short since is made again.
    output_hash: String,
    faces: usize,
    vertices: usize,
}

/// The output mesh of `input` in a batch with `options`.
#[must_use]
pub fn output_path(input: &Input, options: &BatchOptions) -> PathBuf {
    let relative = within(&input.relative);
    let stem = workflow::file_stem(&relative);
    let dir = relative.parent().unwrap_or(Path::new(""));
    options
        .out
        .join(dir)
        .join(format!("{stem}-edited.{}", options.format))
}

fn sidecar_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".json");
    PathBuf::from(s)
}

/// Runs the job on one mesh: reads it, applies the recipe (building its hierarchy first
/// when a step has a level) or the workflow, writes the output and its sidecar — or skips
/// it when its output is up to date. Never panics: a panic of a bug is an `error` row.
#[must_use]
pub fn process(input: &Input, options: &BatchOptions) -> Row {
    let clock = Instant::now();
    let output = output_path(input, options);
    let mut row = Row {
        input: input.path.display().to_string(),
        output: output.display().to_string(),
        status: "error".to_owned(),
        seconds: 0.0,
        faces: 0,
        vertices: 0,
        error: None,
        input_hash: None,
        shard: options.shard.map(|(i, n)| format!("{i}/{n}")),
    };
    let job_hash = options.job_hash();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        process_inner(input, options, &output, &job_hash, &mut row)
    }));
    match result {
        Ok(Ok(status)) => row.status = status.to_owned(),
        Ok(Err(e)) => row.error = Some(e.to_string()),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".to_owned());
            row.error = Some(format!("internal error (please report it): {what}"));
        }
    }
    row.seconds = clock.elapsed().as_secs_f64();
    row
}

fn process_inner(
    input: &Input,
    options: &BatchOptions,
    output: &Path,
    job_hash: &str,
    row: &mut Row,
) -> Result<&'static str> {
    let bytes = std::fs::read(&input.path).map_err(io_error(&input.path))?;
    let input_hash = blake3::hash(&bytes).to_hex().to_string();
    row.input_hash = Some(input_hash.clone());
    drop(bytes);
    let sidecar = sidecar_path(output);
    if output.is_file() {
        if let Some(previous) = std::fs::read(&sidecar)
            .ok()
            .and_then(|b| serde_json::from_slice::<Sidecar>(&b).ok())
        {
            let output_hash = std::fs::read(output)
                .ok()
                .map(|b| blake3::hash(&b).to_hex().to_string());
            if previous.input_hash == input_hash
                && previous.job_hash == job_hash
                && output_hash.as_ref() == Some(&previous.output_hash)
            {
                row.faces = previous.faces;
                row.vertices = previous.vertices;
                return Ok("skipped");
            }
        }
    }
    let mut silent = Silent;
    let loaded = load::load(&input.path, options.weld, &mut silent)?;
    row.faces = loaded.mesh.n_faces();
    row.vertices = loaded.mesh.n_vertices();
    if let Some(dir) = output.parent() {
        std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    }
    // A half-written output must not look finished: the sidecar goes first.
    let _ = std::fs::remove_file(&sidecar);
    let result = match &options.recipe {
        Some(recipe) => run_recipe(loaded, recipe, &mut silent)?,
        None => {
            let done = workflow::run(loaded, &input.path, &options.workflow, &mut silent)?;
            if options.picture > 0 {
                let dir = output
                    .with_file_name(format!("{}-pictures", workflow::file_stem(&input.relative)));
                std::fs::create_dir_all(&dir).map_err(io_error(&dir))?;
                done.write_pictures(&dir, options.picture)?;
            }
            done.result
        }
    };
    halfedge::io::write(output, &result)?;
    let written = std::fs::read(output).map_err(io_error(output))?;
    let record = Sidecar {
        input: input.path.display().to_string(),
        input_hash,
        job_hash: job_hash.to_owned(),
        output_hash: blake3::hash(&written).to_hex().to_string(),
        faces: row.faces,
        vertices: row.vertices,
    };
    let text = serde_json::to_string_pretty(&record).unwrap_or_default();
    std::fs::write(&sidecar, text).map_err(io_error(&sidecar))?;
    Ok("ok")
}

/// Runs `recipe` on a freshly read mesh: on a hierarchy built by the recipe's
/// `[hierarchy]` table (or its defaults) when a step has a level above 0, refined back;
/// on the mesh itself otherwise.
///
/// # Errors
/// The recipe's errors, the hierarchy's.
pub fn run_recipe(
    loaded: load::Loaded,
    recipe: &Recipe,
    progress: &mut dyn Progress,
) -> Result<halfedge::Mesh> {
    let needs_hierarchy = recipe.hierarchy.is_some()
        || recipe
            .steps
            .iter()
            .any(|s| s.level().is_some_and(|l| l > 0));
    let mut mesh = loaded.mesh;
    if !needs_hierarchy {
        recipe::apply_to_mesh(&mut mesh, recipe, progress)?;
        return Ok(mesh);
    }
    let spec = recipe.hierarchy.clone().unwrap_or_default();
    let invalid = |key: &'static str, reason: String| {
        Error::from(RecipeError::Invalid {
            step: 0,
            method: "hierarchy",
            key,
            reason,
        })
    };
    let mut options = match spec.method.as_deref().unwrap_or("rounds") {
        "rounds" => HierarchyOptions::rounds(),
        "qem" => HierarchyOptions::qem(),
        other => return Err(invalid("method", format!("{other:?} is not rounds or qem"))),
    };
    options = options.with_target_faces(spec.target_faces.unwrap_or(2000));
    if let Some(degrees) = spec.max_normal_deviation {
        if !(degrees.is_finite() && degrees > 0.0 && degrees <= 180.0) {
            return Err(invalid(
                "max_normal_deviation",
                format!("must be in (0, 180] degrees, got {degrees}"),
            ));
        }
        options = options.with_max_normal_deviation(degrees.to_radians());
    }
    options = options.with_detail_mode(match spec.detail.as_deref().unwrap_or("local") {
        "local" => DetailMode::LocalFrame,
        "translation" => DetailMode::Translation,
        other => {
            return Err(invalid(
                "detail",
                format!("{other:?} is not local or translation"),
            ))
        }
    });
    let mut hierarchy = Hierarchy::build(mesh, &options)?;
    recipe::apply(&mut hierarchy, recipe, progress)?;
    hierarchy.go_to_level(0)?;
    Ok(hierarchy.into_mesh())
}

/// What a batch did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Meshes in this run (this shard).
    pub meshes: usize,
    /// Processed now.
    pub ok: usize,
    /// Up to date already.
    pub skipped: usize,
    /// Failed (see their rows).
    pub errors: usize,
    /// Seconds of the whole batch.
    pub seconds: f64,
    /// Faces of every mesh read.
    pub faces: usize,
    /// `I/N` when one shard ran.
    pub shard: Option<String>,
}

/// Runs the batch: `inputs` (already sharded) processed `options.jobs` at a time, each
/// row appended to `OUT/report.jsonl` as it finishes, then `OUT/summary.json`; `progress`
/// counts the meshes. Returns the rows (in input order) and the summary.
///
/// # Errors
/// [`Error::Io`] when the output folder or the report cannot be written (a mesh's own
/// failure is its row's, not the batch's); [`Error::InvalidOption`] for zero jobs.
pub fn run(
    inputs: &[Input],
    options: &BatchOptions,
    progress: &mut dyn Progress,
) -> Result<(Vec<Row>, Summary)> {
    use rayon::prelude::*;
    let clock = Instant::now();
    std::fs::create_dir_all(&options.out).map_err(io_error(&options.out))?;
    let mut targets: Vec<(PathBuf, &Path)> = inputs
        .iter()
        .map(|i| (output_path(i, options), i.path.as_path()))
        .collect();
    targets.sort();
    if let Some(pair) = targets.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(Error::InvalidOption {
            option: "INPUTS",
            reason: format!(
                "{} and {} would both be written to {}",
                pair[0].1.display(),
                pair[1].1.display(),
                pair[0].0.display()
            ),
        });
    }
    let report_path = options.out.join("report.jsonl");
    let report = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&report_path)
        .map_err(io_error(&report_path))?;
    let report = Mutex::new(report);
    let threads = match options.jobs {
        Some(0) => {
            return Err(Error::InvalidOption {
                option: "--jobs",
                reason: "at least one job".to_owned(),
            })
        }
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::InvalidOption {
            option: "--jobs",
            reason: e.to_string(),
        })?;
    progress.start("meshes", Some(inputs.len() as u64));
    let done = std::sync::atomic::AtomicU64::new(0);
    let progress = Mutex::new(progress);
    let write_failure: Mutex<Option<Error>> = Mutex::new(None);
    let rows: Vec<Row> = pool.install(|| {
        inputs
            .par_iter()
            .with_max_len(1)
            .map(|input| {
                let row = process(input, options);
                let line = serde_json::to_string(&row).unwrap_or_default();
                if let Ok(mut file) = report.lock() {
                    if let Err(source) = writeln!(file, "{line}").and_then(|()| file.flush()) {
                        if let Ok(mut failure) = write_failure.lock() {
                            failure.get_or_insert(Error::Io {
                                path: report_path.clone(),
                                source,
                            });
                        }
                    }
                }
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                if let Ok(mut p) = progress.lock() {
                    p.advance(n, &row.input);
                }
                row
            })
            .collect()
    });
    if let Ok(p) = progress.into_inner() {
        p.finish();
    }
    if let Some(e) = write_failure.into_inner().ok().flatten() {
        return Err(e);
    }
    let count = |status: &str| rows.iter().filter(|r| r.status == status).count();
    let summary = Summary {
        meshes: rows.len(),
        ok: count("ok"),
        skipped: count("skipped"),
        errors: count("error"),
        seconds: clock.elapsed().as_secs_f64(),
        faces: rows.iter().map(|r| r.faces).sum(),
        shard: options.shard.map(|(i, n)| format!("{i}/{n}")),
    };
    let summary_path = options.out.join(match options.shard {
        Some((i, n)) => format!("summary-{i}-of-{n}.json"),
        None => "summary.json".to_owned(),
    });
    std::fs::write(
        &summary_path,
        serde_json::to_string_pretty(&summary).unwrap_or_default(),
    )
    .map_err(io_error(&summary_path))?;
    Ok((rows, summary))
}

/// The distinct statuses of `rows` (for messages).
#[must_use]
pub fn statuses(rows: &[Row]) -> BTreeSet<&str> {
    rows.iter().map(|r| r.status.as_str()).collect()
}
