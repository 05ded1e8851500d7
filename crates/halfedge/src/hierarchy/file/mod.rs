//! The hierarchy file (`.mrh`): a [`Hierarchy`] saved as it is, to be loaded tomorrow and
//! walked and edited as if it had never left memory (issue 30). The layout, the checks and
//! the version policy are in `docs/guide/hierarchy-file.md`.
//!
//! - **Complete.** The file holds the mesh at the saved level with every slot (live,
//!   removed by a collapse, vacant), its links, states, generations and positions; every
//!   collapse record and its fingerprint, placement and detail coefficients; the level
//!   table; the build's options and how it ended; the sub-mesh label attributes and their
//!   binding; the affine and region marks; the positions edits started from; the current
//!   position and the bookkeeping refinement reads. So `build → save → load →
//!   refine_to(0)` gives the input bit for bit (positions, connectivity, handle indices),
//!   and an edit made before saving refines after loading exactly as it would have.
//! - **Not saved**: attributes other than the label attributes (the attached one and the
//!   mesh's [`LABEL_ATTRIBUTE`](crate::labels::LABEL_ATTRIBUTE)); the collapses made
//!   through [`Mesh::collapse`](crate::Mesh::collapse) behind the hierarchy's back that
//!   still wait for their split (their records stay with the caller); bookmarks
//!   ([`Hierarchy::bookmark`], which name their hierarchy instance). A hierarchy carrying
//!   a [field mark](Hierarchy::mark_field) (a closure) is refused with
//!   [`Error::InvalidArgument`]: refine first, or mark the motion with affine and region
//!   marks.
//! - **Deterministic**: the same hierarchy gives the same bytes (no time, no address, no
//!   hash order, no thread count).
//! - **Safe against any input**: a header with magic, format version and a section table,
//!   a CRC-32 per section and for the header, every count checked against the bytes left
//!   before anything is allocated, every index range-checked, the mesh checked with
//!   [`Mesh::check`](crate::Mesh::check); a loaded hierarchy then *distrusts* its mesh
//!   (as one whose mesh was changed behind its back): every split and collapse goes
//!   through the checked path, so a forged file whose checksums were recomputed is refused
//!   by the walk, step by step, never followed blindly. Every error is
//!   [`Error::Format`] naming the file, the section, the byte and what is wrong.

mod bytes;
mod details;
mod edits;
mod layout;
mod mesh;
mod meta;
mod records;

use std::io::Write;
use std::path::{Path, PathBuf};

use bytes::{format_error, Count, In, Out, Stream};
use layout::SECTIONS;

use super::submesh_labels::LabelBinding;
use super::{next_hierarchy_id, Hierarchy};
use crate::error::{Error, Result};
use crate::handle::VertexId;
use crate::labels::Label;

/// The version of the hierarchy file format this library writes and reads (the
/// `FORMAT_VERSION` field of the header). A reader reads exactly its own version; a file
/// of another version is refused with [`Error::Format`] saying which version it is.
pub const FORMAT_VERSION: u32 = 1;

/// What the sections need besides the hierarchy: the label attributes to keep.
struct Plan<'h> {
    labels: Vec<(&'h str, &'h [Label])>,
    attached: bool,
}

/// Writes section `k` (of [`SECTIONS`]) of `h`.
fn write_section(h: &Hierarchy, plan: &Plan<'_>, k: usize, out: &mut impl Out) {
    match SECTIONS[k] {
        "META" => meta::write(h, out),
        "MESH" => mesh::write(&h.mesh, out),
        "LABL" => mesh::write_labels(&plan.labels, plan.attached, out),
        "RECS" => records::write(&h.records, out),
        "PLAC" => records::write_placements(&h.placements, out),
        "DETL" => details::write(&h.details, out),
        "MARK" => edits::write_marks(&h.marks, out),
        _ => edits::write_rests(&h.rests, out),
    }
}

/// # Saving and loading (`.mrh` files)
impl Hierarchy {
    /// Saves the hierarchy to `path` (see [`write_to`](Self::write_to) for what is
    /// written), through a temporary file beside it renamed into place: an interrupted
    /// save never leaves a truncated file under `path`.
    ///
    /// # Errors
    /// [`Error::Io`] naming the file; the refusals of [`write_to`](Self::write_to).
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut temporary = path.as_os_str().to_owned();
        temporary.push(".partial");
        let temporary = PathBuf::from(temporary);
        let written = (|| -> Result<()> {
            let file = std::fs::File::create(&temporary).map_err(io)?;
            self.write_file(file, path)?;
            std::fs::rename(&temporary, path).map_err(io)
        })();
        if written.is_err() {
            // Nothing of the failed save is left behind (the error is the save's).
            let _ignored = std::fs::remove_file(&temporary);
        }
        written
    }

    /// Writes the hierarchy in the `.mrh` format to `writer`: the mesh at the current
    /// level with every slot, every record with its fingerprint, placement and detail
    /// coefficients, the level table, the options and build outcome, the label attributes
    /// and their binding, the marks, the positions edits started from and the bookkeeping
    /// (see the [module docs](self)). The same hierarchy always gives the same bytes.
    /// Writes through a small buffer of its own (no need for a `BufWriter`).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] (nothing written) when a vertex carries a field mark
    /// ([`mark_field`](Self::mark_field): a closure cannot be saved) or when the label
    /// attribute attached to the hierarchy was removed from its mesh; [`Error::Io`] when
    /// writing fails (its path is `<writer>`).
    pub fn write_to(&self, writer: impl Write) -> Result<()> {
        self.write_file(writer, Path::new("<writer>"))
    }

    fn write_file(&self, mut writer: impl Write, path: &Path) -> Result<()> {
        edits::check_marks(&self.marks)?;
        let (labels, attached) = mesh::label_attributes(self)?;
        let plan = Plan { labels, attached };
        let mut lengths = [0u64; SECTIONS.len()];
        for (k, length) in lengths.iter_mut().enumerate() {
            let mut count = Count::default();
            write_section(self, &plan, k, &mut count);
            *length = count.0;
        }
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut stream = Stream::new(&mut writer);
        stream.unhashed(&layout::header(&lengths)).map_err(io)?;
        for (k, &length) in lengths.iter().enumerate() {
            write_section(self, &plan, k, &mut stream);
            let (written, crc) = stream.finish().map_err(io)?;
            debug_assert_eq!(written, length, "section {}", SECTIONS[k]);
            stream.unhashed(&crc.to_le_bytes()).map_err(io)?;
        }
        drop(stream);
        writer.flush().map_err(io)
    }

    /// Loads a hierarchy saved by [`save`](Self::save) (see
    /// [`read_from`](Self::read_from)).
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read; the errors of
    /// [`read_from`](Self::read_from).
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::read_from(&bytes, path)
    }

    /// Reads a hierarchy from the bytes of a `.mrh` file (`path` names it in errors). The
    /// hierarchy comes back at the saved level with everything it held (see the
    /// [module docs](self)), a new instance (bookmarks of the saved one do not fit it),
    /// and *distrusting* its mesh: its walks check every split and collapse against the
    /// mesh (as after a change behind its back), so a file forged to pass every check
    /// below is refused by the walk rather than followed.
    ///
    /// Checked before anything is built: the header (magic, [`FORMAT_VERSION`], the
    /// section table, its CRC-32), every section's CRC-32, every count against the bytes
    /// left (before allocating), every field in its range (options, level table,
    /// record, neighbour, mark and slot indices, finite positions), the mesh with
    /// [`Mesh::check`](crate::Mesh::check), and the records against the saved level
    /// (collapsed records' removed vertices are removed, the others' are live, no vertex
    /// removed twice).
    ///
    /// # Errors
    /// [`Error::Format`] naming `path`, the section, the byte and what is wrong, for a
    /// file that is truncated, corrupt, of another version or inconsistent.
    pub fn read_from(bytes: &[u8], path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let sections = layout::sections(bytes, path)?;
        {
            use rayon::prelude::*;
            // The CRC-32s of the large sections on all cores; the first bad one in
            // file order is reported.
            let checked: Vec<Result<()>> =
                sections.par_iter().map(|s| s.verify(path)).collect();
            checked.into_iter().collect::<Result<()>>()?;
        }
        let input =
            |k: usize| In::new(sections[k].bytes, sections[k].offset, sections[k].tag, path);
        // The mesh on one core, the records and everything indexed by them on the other
        // (their indices are checked against the slot counts read ahead).
        let (nv, nh) = mesh::slot_counts(&mut input(1))?;
        let (mesh_side, records_side) = rayon::join(
            || -> Result<_> {
                let meta = meta::read(&mut input(0))?;
                let mesh = mesh::read(&mut input(1))?;
                let labels = mesh::read_labels(&mut input(2), nv)?;
                Ok((meta, mesh, labels))
            },
            || -> Result<_> {
                let records = records::read(&mut input(3), (nv, nh))?;
                let n = records.len();
                let placements = records::read_placements(&mut input(4), n)?;
                let details = details::read(&mut input(5), n, nv)?;
                let marks = edits::read_marks(&mut input(6))?;
                let rests = edits::read_rests(&mut input(7), n, nv)?;
                Ok((records, placements, details, marks, rests))
            },
        );
        let (meta, mut mesh, labels) = mesh_side?;
        let (records, placements, details, marks, rests) = records_side?;
        debug_assert_eq!((nv, nh), (mesh.vertex_slots(), mesh.halfedge_slots()));
        let n = records.len();
        let (records_in, marks_in) = (input(3), input(6));

        let fail = |section: &str, what: String| {
            Err(format_error(path, format!("section {section}: {what}")))
        };
        if meta.level_ends.last().is_some_and(|&e| e > n) {
            return fail("META", format!("the level table runs past the {n} records"));
        }
        if meta.applied > n || meta.consistent_from > n {
            return fail(
                "META",
                format!(
                    "{} records collapsed (consistent from {}) of {n}",
                    meta.applied, meta.consistent_from
                ),
            );
        }
        if meta.method != meta.options.method || details.mode() != meta.options.detail_mode {
            return fail(
                "META",
                "the method or detail mode differs from the build options".into(),
            );
        }
        if meta.labels_defined_at.is_some() != labels.attached
            || meta.labels_defined_at.is_some_and(|d| d > n)
        {
            return fail(
                "META",
                "the labels' binding does not match the label attributes".into(),
            );
        }
        if marks.of_vertex.len() > nv {
            return Err(marks_in.error(format!(
                "{} vertex marks for {nv} vertex slots",
                marks.of_vertex.len()
            )));
        }
        check_records_against_level(&records, &mesh, meta.applied)
            .map_err(|what| records_in.error(what))?;

        let mut attached = None;
        for (k, (name, values)) in labels.attributes.into_iter().enumerate() {
            let attribute = mesh
                .add_vertex_attribute::<Label>(&name, 0)
                .map_err(|e| format_error(path, format!("section LABL: {e}")))?;
            mesh.attribute_values_mut(attribute)?
                .copy_from_slice(&values);
            if k == 0 && labels.attached {
                attached = Some(attribute);
            }
        }
        let binding = mesh.binding();
        let mut records = records;
        // The walks' checked splits vouch for the records against this mesh instance.
        records.origin = Some(binding);
        Ok(Self {
            clean_positions: meta.clean.then_some(binding),
            stamp: None,
            rests,
            consistent_from: meta.consistent_from,
            mesh,
            records,
            placements,
            details,
            marks,
            level_ends: meta.level_ends,
            level_faces: meta.level_faces,
            applied: meta.applied,
            method: meta.method,
            options: meta.options,
            labels: attached.map(|attribute| LabelBinding {
                attribute,
                defined_at: meta.labels_defined_at.unwrap_or(0),
            }),
            outcome: meta.outcome,
            id: next_hierarchy_id(),
            refreshes: meta.refreshes,
        })
    }
}

/// Reads only the mesh of a `.mrh` file (at the level the hierarchy was saved at, its
/// collapsed elements kept as removed ones), without the records: for showing a saved
/// hierarchy, or telling what it holds, at a fraction of the cost of
/// [`Hierarchy::read_from`]. The header and the mesh section are checked as
/// `read_from` checks them (its CRC-32, every count and link, [`Mesh::check`]); no
/// label or other attribute is attached.
///
/// # Errors
/// [`Error::Format`] naming `path`, as [`Hierarchy::read_from`].
///
/// [`Mesh::check`]: crate::Mesh::check
pub fn read_mesh(bytes: &[u8], path: impl AsRef<Path>) -> Result<crate::mesh::Mesh> {
    let path = path.as_ref();
    let section = layout::sections(bytes, path)?[1];
    section.verify(path)?;
    mesh::read(&mut In::new(section.bytes, section.offset, section.tag, path))
}

/// Checks the records against the mesh at the saved level, `applied` of them collapsed:
/// each removes a vertex no other record removes; a collapsed record's removed vertex is
/// a tombstone; a record still to collapse joins two live vertices by a live halfedge.
fn check_records_against_level(
    records: &super::records::Records,
    mesh: &crate::mesh::Mesh,
    applied: usize,
) -> std::result::Result<(), String> {
    let mut removed = vec![false; mesh.vertex_slots()];
    let vertex = |i: u32| -> VertexId { mesh.vh(i) };
    for (r, s) in records.steps.iter().enumerate() {
        let i0 = s.v0 as usize;
        if std::mem::replace(&mut removed[i0], true) {
            return Err(format!(
                "record {r} removes vertex {i0}, which an earlier record removed"
            ));
        }
        let fits = if r < applied {
            mesh.is_deleted_vertex(vertex(s.v0))
                && mesh.halfedge_slots_.is_tombstone(mesh.hh(s.v0v1))
        } else {
            mesh.is_valid_vertex(vertex(s.v0))
                && mesh.is_valid_vertex(vertex(s.v1))
                && mesh.halfedge_slots_.is_live_index(s.v0v1 as usize)
        };
        if !fits {
            return Err(format!(
                "record {r} does not fit the mesh at the saved level ({applied} records \
                 collapsed): its vertices or edge are not {}",
                if r < applied { "removed" } else { "live" }
            ));
        }
    }
    Ok(())
}
