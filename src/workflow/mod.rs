//! The whole multiresolution job, the one `multires workflow` runs (and the `workflow`
//! example, and `multires batch` without a recipe): load → simplify to a level → label a
//! sub-mesh by a cutting plane → one edit of each family (a Lee 1999 area drag, a Bendels &
//! Klein handle rotation, a sub-mesh taper) → refine back with the detail coefficients →
//! write the mesh and before/after pictures, with a summary table.
//!
//! ```text
//! multires workflow [FILE] [--level N] [--method rounds|qem] [--axis y] [--plane 0.72]
//!     [--skip lee,blend,taper] [--weld auto|off|F] [--out DIR]
//! ```
//!
//! It runs on any mesh — closed or open, one component or several, any genus — because
//! each step chooses its region by rules that adapt to the mesh, and says which rule it
//! used:
//!
//! - **Welding**: a mesh written as a triangle soup or with seams (faces on their own
//!   copies of vertices at the same place) is welded first (`Mesh::welded`), when that
//!   closes boundaries; `--weld off` keeps the file's vertices, `--weld F` merges
//!   vertices within `F` times the bounding-box diagonal.
//! - **Level**: `--level` (default 3), but never coarser than the coarsest level with at
//!   least 500 faces (or the input's faces, when it has fewer): edits on a handful of
//!   faces would mean nothing.
//! - **Sub-mesh** (for the taper): the part cut off by a plane perpendicular to `--axis`
//!   (default `y`, up) at `--plane` of the mesh's extent along it (default 0.72), near
//!   the vertex furthest along the axis; the part on the axis' side is the sub-mesh, and
//!   separate components go with the side their centroid lies on. Where that section
//!   runs into the mesh boundary (an open mesh), does not separate the mesh (it goes
//!   around a handle) or cuts off fewer than 4 vertices, the plane moves towards the tip
//!   in steps of 4 % of the extent, then away from it; where no height works, the other
//!   axes are tried (`y`, `z`, `x`, `-y`, `-z`, `-x`). Where no section is a closed
//!   loop at all (an open mesh: a terrain, a flat or partial scan), the sub-mesh is the
//!   part beyond the same planes reached from the tip without crossing them, given as a
//!   vertex mask (the hierarchy then carries no labels for it).
//! - **Lee area** (dragged along the normal): a disk of about a twelfth of the coarse
//!   vertices (30 to 5,000) around the vertex of the largest component furthest to the
//!   front (+z). Where the disk reaches the mesh boundary or wraps around a handle it is
//!   halved (down to a vertex and its ring); then the largest component's extreme
//!   vertices along `x`, `-x`, `y`, `-y`, `-z` are tried, and last the vertex farthest
//!   from the boundary.
//! - **Bendels & Klein** (handle rotated 25° and pulled): the handle is the vertices
//!   within an edge-path distance of 8 % of the bounding-box diagonal from the vertex
//!   furthest along −x, the fixed region everything beyond 30 %; where the handle would
//!   touch the fixed region or either is empty, both radii are halved (three times at
//!   most); where no radius works (the vertex is on a small loose part), the same around
//!   the vertex furthest along −x of the largest component.
//!
//! A step none of whose rules applies is left out with a note saying why and which flag
//! changes it; the job goes on. The pictures are framed on the union of the before and
//! after meshes, so a part an edit pulled out stays in the frame.
//!
//! ```no_run
//! use multires::load::{self, Weld};
//! use multires::progress::Silent;
//! use multires::workflow::{self, WorkflowOptions};
//! # fn main() -> multires::Result<()> {
//! let path = std::path::Path::new("data/blob.obj");
//! let loaded = load::load(path, Weld::Auto, &mut Silent)?;
//! let mut done = workflow::run(loaded, path, &WorkflowOptions::default(), &mut Silent)?;
//! done.write(std::path::Path::new("out"), "ply", 640, &mut Silent)?;
//! print!("{}", done.table());
//! # Ok(())
//! # }
//! ```

mod blend;
mod lee;
pub mod picks;

use std::path::{Path, PathBuf};
use std::time::Instant;

use edit::deform::{Propagation, SubmeshEdit, Variation};
use edit::HierarchyEdit;
use glam::DVec3;
use halfedge::hierarchy::{BuildProgress, Hierarchy, HierarchyOptions, Method};
use halfedge::Mesh;

use crate::error::{Error, Result};
use crate::load::Loaded;
use crate::memory::PeakMeter;
use crate::progress::{self, Progress};
use crate::render::{self, Camera, Panel};

/// The edit level keeps at least this many faces (or all of a smaller input's).
pub const MIN_EDIT_FACES: usize = 500;

/// The workflow's options (the command line's flags; see the [module docs](self) for the
/// rules they steer).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct WorkflowOptions {
    /// Hierarchy level to edit at (0 = the input; clamped to the coarsest level with at
    /// least [`MIN_EDIT_FACES`] faces). Default 3.
    pub level: usize,
    /// Simplification: the paper's rounds (default) or QEM.
    pub method: Method,
    /// Axis of the cutting plane that labels the sub-mesh: the sub-mesh is the part
    /// furthest along it. Default `+y`.
    pub axis: DVec3,
    /// Height of the cutting plane, as a fraction of the mesh's extent along the axis, in
    /// `[0, 1)`. Default 0.72.
    pub plane: f64,
    /// Leave out the Lee area drag.
    pub skip_lee: bool,
    /// Leave out the Bendels & Klein rotation.
    pub skip_blend: bool,
    /// Leave out the sub-mesh taper (and its labelling).
    pub skip_taper: bool,
}

impl Default for WorkflowOptions {
    fn default() -> Self {
        Self {
            level: 3,
            method: Method::Rounds,
            axis: DVec3::Y,
            plane: 0.72,
            skip_lee: false,
            skip_blend: false,
            skip_taper: false,
        }
    }
}

impl WorkflowOptions {
    /// The same options editing at `level`.
    #[must_use]
    pub fn with_level(mut self, level: usize) -> Self {
        self.level = level;
        self
    }
    /// The same options simplifying by `method`.
    #[must_use]
    pub fn with_method(mut self, method: Method) -> Self {
        self.method = method;
        self
    }
    /// The same options cutting the sub-mesh perpendicular to `axis` at `plane`.
    #[must_use]
    pub fn with_plane(mut self, axis: DVec3, plane: f64) -> Self {
        self.axis = axis;
        self.plane = plane;
        self
    }
    /// The same options leaving out the steps named in `steps` (`lee`, `blend`, `taper`).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for another name.
    pub fn with_skipped(mut self, steps: &[impl AsRef<str>]) -> Result<Self> {
        for step in steps {
            match step.as_ref() {
                "lee" => self.skip_lee = true,
                "blend" => self.skip_blend = true,
                "taper" => self.skip_taper = true,
                other => {
                    return Err(Error::InvalidOption {
                        option: "--skip",
                        reason: format!("unknown step {other:?} (lee, blend or taper)"),
                    })
                }
            }
        }
        Ok(self)
    }
}

/// The stem of a mesh file's name, without its format's extension (and without `.gz`):
/// `bunny` for `bunny.obj` and `bunny.obj.gz`; `mesh` when there is none.
#[must_use]
pub fn file_stem(path: &Path) -> String {
    let name = path.file_name().and_then(|s| s.to_str()).unwrap_or("mesh");
    let name = name.strip_suffix(".gz").unwrap_or(name);
    Path::new(name)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("mesh")
        .to_owned()
}

/// One row of the workflow's table: a step, what it did, and how long it took.
#[derive(Clone, Debug, PartialEq)]
pub struct StepReport {
    /// The step (`load`, `simplify`, `label`, `Lee drag`, `B&K rotate`, `taper`,
    /// `refine`, `write`).
    pub step: &'static str,
    /// What it did, in words (or why it was left out: `skipped: …`).
    pub detail: String,
    /// Seconds it took.
    pub seconds: f64,
    /// The process's peak resident memory during the step, in bytes (for `load`, the
    /// peak before the workflow began: the reading); `None` where the platform does not
    /// report it (see [`crate::memory`]).
    pub peak_bytes: Option<u64>,
}

fn skipped(step: &'static str, why: &str) -> StepReport {
    StepReport {
        step,
        detail: format!("skipped: {why}"),
        seconds: 0.0,
        peak_bytes: None,
    }
}

/// A copy of `mesh` without its tombstones (a coarse level keeps every slot of the
/// input; its copy for the pictures needs the live elements only).
fn compact_copy(mesh: &Mesh) -> Result<Mesh> {
    let (positions, triangles) = mesh.to_arrays();
    Ok(Mesh::from_arrays(&positions, &triangles)?.0)
}

/// The input mesh again: the fully refined `result`'s connectivity (the input's, slot
/// for slot: collapses and splits are exact inverses) with the input's `positions`.
fn input_again(result: &Mesh, positions: Vec<DVec3>) -> Result<Mesh> {
    if positions.len() != result.vertex_slots() {
        return Err(
            halfedge::Error::Invariant(halfedge::Invariant::Counts(format!(
                "the refined mesh has {} vertex slots, the input {}",
                result.vertex_slots(),
                positions.len()
            )))
            .into(),
        );
    }
    let mut original = result.clone();
    original.positions_mut().copy_from_slice(&positions);
    Ok(original)
}

/// A finished workflow: the edited mesh at full resolution, the meshes its pictures show,
/// and its table and notes.
#[derive(Clone, Debug)]
pub struct Workflow {
    /// The input (after welding). Made again at the end from the refined mesh's
    /// connectivity (a full refinement restores the input's slots bit for bit) and the
    /// input's positions, so that the job never holds two full-resolution meshes while
    /// the hierarchy lives.
    pub original: Mesh,
    /// The edited mesh at full resolution.
    pub result: Mesh,
    /// The edited level before the edits, as a compact copy (its live elements only,
    /// numbered afresh as [`Mesh::to_arrays`] numbers them: not the hierarchy's slots).
    pub coarse_before: Mesh,
    /// The edited level after the edits, compact like
    /// [`coarse_before`](Self::coarse_before) (the same numbering).
    pub coarse_after: Mesh,
    /// The level the edits were made at.
    pub level: usize,
    /// The input's file (its stem names the outputs).
    pub source: PathBuf,
    /// The table's rows, in order.
    pub rows: Vec<StepReport>,
    /// Notes: what a rule had to adapt, what was left out and which flag changes it.
    pub notes: Vec<String>,
    /// Seconds the hierarchy's build took (within the `simplify` row).
    pub build_seconds: f64,
}

/// Runs the workflow on `loaded` (read from `source`, see [`crate::load`]); the long
/// steps are steps of `progress`.
///
/// # Errors
/// [`Error::InvalidOption`] for a plane outside `[0, 1)`; [`Error::NoFaces`] for a mesh
/// without faces; the kernel's errors (a mesh that fails `check`, a refused walk). A step
/// whose rules find no region is left out with a note, not an error.
pub fn run(
    loaded: Loaded,
    source: &Path,
    options: &WorkflowOptions,
    progress: &mut dyn Progress,
) -> Result<Workflow> {
    run_timed(loaded, source, options, progress, 0.0)
}

/// [`run`], the `load` row counting `load_seconds` spent reading before.
pub fn run_timed(
    loaded: Loaded,
    source: &Path,
    options: &WorkflowOptions,
    progress: &mut dyn Progress,
    load_seconds: f64,
) -> Result<Workflow> {
    if !(options.plane >= 0.0 && options.plane < 1.0) {
        return Err(Error::InvalidOption {
            option: "--plane",
            reason: format!("must be in [0, 1), got {}", options.plane),
        });
    }
    let path = source;
    let mut rows = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    let clock = Instant::now();
    let Loaded {
        mesh: input,
        build: report,
        welding,
    } = loaded;
    notes.extend(welding.map(|w| w.note));
    progress::step(progress, "checking the mesh", || input.check())?;
    if input.n_faces() == 0 {
        return Err(Error::NoFaces {
            path: path.to_owned(),
        });
    }
    let topology = input.topology_report();
    rows.push(StepReport {
        step: "load",
        detail: format!(
            "{}: {} vertices, {} faces, {} component(s), {} boundary loop(s), Euler {} \
             ({} duplicated vertices, {} dropped faces)",
            path.display(),
            input.n_vertices(),
            input.n_faces(),
            topology.components,
            topology.boundary_loops,
            topology.euler,
            report.duplicated_vertices,
            report.dropped_faces
        ),
        seconds: load_seconds + clock.elapsed().as_secs_f64(),
        peak_bytes: crate::memory::peak_resident_bytes(),
    });
    // The input's positions, not a copy of the mesh: the refinement gives its
    // connectivity back.
    let original_positions = input.positions().to_vec();
    let (lo, hi) = input.bounding_box().ok_or(Error::NoVertices)?;
    let diagonal = lo.distance(hi);

    // --- simplify ---------------------------------------------------------------
    let hierarchy_options = match options.method {
        Method::Qem => HierarchyOptions::qem(),
        _ => HierarchyOptions::rounds(),
    };
    let clock = Instant::now();
    let meter = PeakMeter::start();
    let input_faces = input.n_faces();
    progress.start("simplifying (faces removed)", Some(input_faces as u64));
    let built =
        Hierarchy::build_with_progress(input, &hierarchy_options, &mut |p: BuildProgress| {
            progress.advance(
                (p.input_faces - p.faces) as u64,
                &format!("simplifying (level {})", p.levels),
            );
        });
    progress.finish();
    let mut hierarchy = built?;
    let build_seconds = clock.elapsed().as_secs_f64();
    let min_faces = MIN_EDIT_FACES.min(input_faces);
    let finest_enough = hierarchy
        .level_face_counts()
        .iter()
        .rposition(|&f| f >= min_faces)
        .unwrap_or(0);
    let level = options.level.min(finest_enough);
    if level < options.level {
        notes.push(format!(
            "editing at level {level} ({} faces) instead of {}: the levels above it have \
             fewer than {min_faces} faces (--level chooses; {:?})",
            hierarchy.level_face_counts()[level],
            options.level,
            hierarchy.level_face_counts()
        ));
    }
    let clock = Instant::now();
    hierarchy.go_to_level(level)?;
    rows.push(StepReport {
        step: "simplify",
        detail: format!(
            "{} levels {:?} faces; editing at level {level} ({} faces of {input_faces})",
            hierarchy.n_levels(),
            hierarchy.level_face_counts(),
            hierarchy.mesh().n_faces()
        ),
        seconds: build_seconds + clock.elapsed().as_secs_f64(),
        peak_bytes: meter.peak(),
    });

    // --- label a sub-mesh by a cutting plane ------------------------------------
    let clock = Instant::now();
    let meter = PeakMeter::start();
    let sub = if options.skip_taper {
        rows.push(skipped("label", "left out (--skip taper)"));
        None
    } else {
        match crate::cut::label_submesh(hierarchy.mesh_mut(), options.axis, options.plane) {
            Ok(labelled) => {
                hierarchy.attach_labels(labelled.attribute)?;
                hierarchy.labels_defined_here();
                notes.extend(labelled.note.clone());
                rows.push(StepReport {
                    step: "label",
                    detail: labelled.detail.clone(),
                    seconds: clock.elapsed().as_secs_f64(),
                    peak_bytes: meter.peak(),
                });
                Some(labelled.sub)
            }
            Err(why) => {
                match crate::cut::mask_submesh(hierarchy.mesh(), options.axis, options.plane) {
                    // An open mesh (a terrain, a flat or partial scan): no section is a
                    // closed loop, but the part beyond the plane is still a sub-mesh.
                    Ok((sub, detail)) => {
                        notes.push(format!(
                            "no plane section is a closed frontier ({why}); the sub-mesh is \
                             the part beyond the plane reached from its tip, given to the \
                             taper as a vertex mask (no labels: the hierarchy's levels were \
                             not kept from crossing it)"
                        ));
                        rows.push(StepReport {
                            step: "label",
                            detail,
                            seconds: clock.elapsed().as_secs_f64(),
                            peak_bytes: meter.peak(),
                        });
                        Some(sub)
                    }
                    Err(_) => {
                        notes.push(format!("sub-mesh taper left out: {why}"));
                        rows.push(skipped("label", "no cutting plane applies (see notes)"));
                        None
                    }
                }
            }
        }
    };
    let coarse_before = compact_copy(hierarchy.mesh())?;

    // --- Lee 1999: drag an editing area on the front ----------------------------
    if options.skip_lee {
        rows.push(skipped("Lee drag", "left out (--skip lee)"));
    } else {
        let clock = Instant::now();
        let meter = PeakMeter::start();
        match lee::lee_drag(&mut hierarchy, diagonal, progress) {
            Ok((detail, note)) => {
                notes.extend(note);
                rows.push(StepReport {
                    step: "Lee drag",
                    detail,
                    seconds: clock.elapsed().as_secs_f64(),
                    peak_bytes: meter.peak(),
                });
            }
            Err(why) => {
                notes.push(format!(
                    "Lee area drag left out: {why} (--skip lee leaves it out without trying)"
                ));
                rows.push(skipped("Lee drag", "no editing area applies (see notes)"));
            }
        }
    }

    // --- Bendels & Klein: rotate a handle on the side ----------------------------
    let mut landing: Option<blend::Landing> = None;
    if options.skip_blend {
        rows.push(skipped("B&K rotate", "left out (--skip blend)"));
    } else {
        let clock = Instant::now();
        let meter = PeakMeter::start();
        match blend::blend_rotate(&mut hierarchy, diagonal, progress) {
            Ok((detail, note, to_land)) => {
                notes.extend(note);
                landing = Some(to_land);
                rows.push(StepReport {
                    step: "B&K rotate",
                    detail,
                    seconds: clock.elapsed().as_secs_f64(),
                    peak_bytes: meter.peak(),
                });
            }
            Err(why) => {
                notes.push(format!(
                    "Bendels & Klein rotation left out: {why} (--skip blend leaves it out \
                     without trying)"
                ));
                rows.push(skipped("B&K rotate", "no regions apply (see notes)"));
            }
        }
    }

    // --- sub-mesh taper above the plane -----------------------------------------
    let before_taper = hierarchy.mesh().positions().to_vec();
    if let Some(sub) = &sub {
        let clock = Instant::now();
        let meter = PeakMeter::start();
        let taper = SubmeshEdit::Taper {
            axis: None,
            factor: 0.6,
            variation: Variation::Levels(None),
        };
        // Marked in the hierarchy: its region (the sub-mesh) and the part at full
        // strength, which lands exactly when refined.
        let tapered = sub
            .apply_with_marks(hierarchy.mesh_mut(), &taper, Propagation::linear(2))
            .map_err(edit::Error::from)
            .and_then(|applied| applied.mark(&mut hierarchy));
        match tapered {
            Ok(_) => rows.push(StepReport {
                step: "taper",
                detail: "sub-mesh tapered to 0.6, 2 propagation levels".to_string(),
                seconds: clock.elapsed().as_secs_f64(),
                peak_bytes: meter.peak(),
            }),
            Err(e) => {
                notes.push(format!(
                    "sub-mesh taper left out: {e} (--axis and --plane choose another \
                     sub-mesh, --skip taper leaves it out)"
                ));
                rows.push(skipped("taper", "the taper failed (see notes)"));
            }
        }
    }
    hierarchy.mesh().check()?;
    let coarse_after = compact_copy(hierarchy.mesh())?;
    // Handle vertices the taper moved too: their fine vertices are the taper's image of
    // the handle's, not the handle's alone.
    let handle_tapered = landing.as_ref().map_or(0, |landing| {
        let after = hierarchy.mesh().positions();
        landing
            .handle
            .iter()
            .filter(|&&i| before_taper[i as usize] != after[i as usize])
            .count()
    });
    drop(before_taper);

    // --- refine back with detail coefficients -----------------------------------
    let clock = Instant::now();
    let meter = PeakMeter::start();
    progress.start("refining (levels) back to the input", Some(level as u64));
    let mut refined = Ok(());
    for (k, l) in (0..level).rev().enumerate() {
        refined = hierarchy.go_to_level(l);
        if refined.is_err() {
            break;
        }
        progress.advance(
            k as u64 + 1,
            &format!("refining ({} faces)", hierarchy.mesh().n_faces()),
        );
    }
    progress.finish();
    refined?;
    let ancestors = hierarchy.ancestors(level)?;
    let result = hierarchy.into_mesh();
    // The check and the input's copy read the result only: side by side.
    let (checked, original) = progress::step(progress, "checking the result", || {
        rayon::join(
            || result.check(),
            || input_again(&result, original_positions),
        )
    });
    checked?;
    let original = original?;
    // How exactly the handle landed: its fine vertices against the rigid image of their
    // input positions (later edits that moved the handle too make this larger).
    let landed = landing.map(|landing| landing.measure(&original, &result, &ancestors, diagonal));
    let moved = result
        .vertices()
        .filter(|&v| result.position(v) != original.position(v))
        .count();
    rows.push(StepReport {
        step: "refine",
        detail: format!(
            "back to {} vertices, {} faces; {moved} vertices moved, {} kept bit for bit{}",
            result.n_vertices(),
            result.n_faces(),
            result.n_vertices() - moved,
            landed.map_or(String::new(), |(count, worst)| format!(
                "; the B&K handle's {count} vertices are its rigid image within {worst:.1e} \
                 of the diagonal{}",
                if handle_tapered > 0 {
                    format!(
                        " ({handle_tapered} of its coarse vertices were tapered afterwards: \
                         --skip taper leaves them as the rotation put them)"
                    )
                } else {
                    String::new()
                }
            ))
        ),
        seconds: clock.elapsed().as_secs_f64(),
        peak_bytes: meter.peak(),
    });
    Ok(Workflow {
        original,
        result,
        coarse_before,
        coarse_after,
        level,
        source: path.to_owned(),
        rows,
        notes,
        build_seconds,
    })
}

impl Workflow {
    /// The output mesh's path in `out`: the input's stem with `-edited.FORMAT`.
    #[must_use]
    pub fn output_path(&self, out: &Path, format: &str) -> PathBuf {
        out.join(format!("{}-edited.{format}", file_stem(&self.source)))
    }

    /// Writes the edited mesh (as [`output_path`](Self::output_path)) and the pictures
    /// (see [`write_pictures`](Self::write_pictures)) into `out` (made if missing), and
    /// adds the `write` row.
    ///
    /// # Errors
    /// [`Error::Io`] when the folder cannot be made; the writer's and the renderer's
    /// errors.
    pub fn write(
        &mut self,
        out: &Path,
        format: &str,
        picture: usize,
        progress: &mut dyn Progress,
    ) -> Result<PathBuf> {
        let clock = Instant::now();
        let meter = PeakMeter::start();
        std::fs::create_dir_all(out).map_err(crate::error::io_error(out))?;
        let out_mesh = self.output_path(out, format);
        progress::step(progress, &format!("writing {}", out_mesh.display()), || {
            halfedge::io::write(&out_mesh, &self.result)
        })?;
        self.write_pictures(out, picture)?;
        self.rows.push(StepReport {
            step: "write",
            detail: format!(
                "{} and before/after pictures in {}",
                out_mesh.display(),
                out.display()
            ),
            seconds: clock.elapsed().as_secs_f64(),
            peak_bytes: meter.peak(),
        });
        Ok(out_mesh)
    }

    /// Writes the pictures `before.png`, `after.png`, `before-after.png` and
    /// `coarse-edit.png` into `out` (which must exist): panels `picture` pixels wide and
    /// 3/4 as high, framed on the union of every mesh shown, the after panel coloured by
    /// displacement.
    ///
    /// # Errors
    /// The renderer's errors (a picture size out of range), [`Error::Io`]-like errors of
    /// the PNG writer.
    pub fn write_pictures(&self, out: &Path, picture: usize) -> Result<()> {
        let (w, h) = (picture, picture * 3 / 4);
        let (original, result) = (&self.original, &self.result);
        // One frame for every picture: the union of the before and after meshes.
        let frame =
            render::union_bounds([original, result, &self.coarse_before, &self.coarse_after]);
        let camera = Camera::default();
        let (lo, hi) = original.bounding_box().ok_or(Error::NoVertices)?;
        let colors = render::displacement_colors(original, result, 0.05 * lo.distance(hi));
        let before = render::render(Panel::new(original), &camera, frame, w, h)?;
        let after = render::render(Panel::with_colors(result, &colors), &camera, frame, w, h)?;
        let coarse = render::render_side_by_side(
            &[
                Panel::new(&self.coarse_before),
                Panel::new(&self.coarse_after),
            ],
            &camera,
            frame,
            (w / 2).max(1),
            (h / 2).max(1),
        )?;
        before.save_png(out.join("before.png"))?;
        after.save_png(out.join("after.png"))?;
        render::Image::side_by_side(&[&before, &after])?.save_png(out.join("before-after.png"))?;
        coarse.save_png(out.join("coarse-edit.png"))?;
        Ok(())
    }

    /// The highest of the steps' peak resident memory, in bytes (`None` where the
    /// platform does not report it).
    #[must_use]
    pub fn peak_bytes(&self) -> Option<u64> {
        self.rows.iter().filter_map(|r| r.peak_bytes).max()
    }

    /// The table the command line prints: one row per step with its seconds and peak
    /// memory, the total, then the notes.
    #[must_use]
    pub fn table(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let gb =
            |bytes: Option<u64>| bytes.map_or("-".to_owned(), |b| format!("{:.2}", b as f64 / 1e9));
        let _ = writeln!(
            s,
            "{:<11} {:>9} {:>7}  details",
            "step", "seconds", "peak GB"
        );
        for row in &self.rows {
            let _ = writeln!(
                s,
                "{:<11} {:>9.3} {:>7}  {}",
                row.step,
                row.seconds,
                gb(row.peak_bytes),
                row.detail
            );
        }
        let _ = writeln!(
            s,
            "{:<11} {:>9.3} {:>7}",
            "total",
            self.rows.iter().map(|r| r.seconds).sum::<f64>(),
            gb(self.peak_bytes())
        );
        for note in &self.notes {
            let _ = writeln!(s, "note: {note}");
        }
        s
    }
}
