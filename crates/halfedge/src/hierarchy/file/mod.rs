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

/// The version of the hierarchy file format this library writes (the `FORMAT_VERSION`
/// field of the header). It reads this version and every one from
/// [`OLDEST_READABLE_VERSION`]; a file of another version is refused with
/// [`Error::Format`] saying which version it is. Version 2 added the codes 2 and 3 of
/// the options' method byte (rounds placing survivors by the quadric); a version 1 file
/// is a version 2 file without them.
pub const FORMAT_VERSION: u32 = 2;

/// The oldest hierarchy file format version this library reads (see [`FORMAT_VERSION`]).
pub const OLDEST_READABLE_VERSION: u32 = 1;

/// What the sections need besides the hierarchy: the label attributes to keep.
struct Plan<'h> {
    labels: Vec<mesh::LabelColumn<'h>>,
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
        use std::io::{BufReader, Read, Seek, SeekFrom};
        let path = path.as_ref();
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        // Streamed: each section is read a chunk at a time and decoded as it comes (no
        // copy of the whole file in memory), the mesh on one core and the records on
        // the other, each from its own handle on the file.
        let open_at = |offset: usize| -> Result<BufReader<std::fs::File>> {
            let mut file = std::fs::File::open(path).map_err(io)?;
            file.seek(SeekFrom::Start(offset as u64)).map_err(io)?;
            Ok(BufReader::with_capacity(1 << 16, file))
        };
        let mut file = std::fs::File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let mut head = vec![0u8; (layout::HEADER as u64).min(len) as usize];
        file.read_exact(&mut head).map_err(io)?;
        let entries = layout::table(&head, len, path)?;
        let mesh_at = entries[1];
        let counts = mesh::slot_counts(&mut In::stream(
            &mut open_at(mesh_at.offset)?,
            mesh_at.length,
            mesh_at.offset,
            "MESH",
            path,
        ))?;
        let (mesh_side, records_side) = rayon::join(
            || {
                let mut reader = BufReader::with_capacity(1 << 16, file);
                read_mesh_side(&mut Sections::Stream(&mut reader, &entries), path, counts)
            },
            || {
                let mut reader = open_at(entries[3].offset)?;
                read_records_side(&mut Sections::Stream(&mut reader, &entries), path, counts)
            },
        );
        Self::assemble(path, counts, mesh_side?, records_side?)
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
            let checked: Vec<Result<()>> = sections.par_iter().map(|s| s.verify(path)).collect();
            checked.into_iter().collect::<Result<()>>()?;
        }
        let mesh_at = sections[1];
        let counts = mesh::slot_counts(&mut In::new(mesh_at.bytes, mesh_at.offset, "MESH", path))?;
        // The mesh on one core, the records and everything indexed by them on the other
        // (their indices are checked against the slot counts read ahead).
        let (mesh_side, records_side) = rayon::join(
            || read_mesh_side(&mut Sections::Slices(&sections), path, counts),
            || read_records_side(&mut Sections::Slices(&sections), path, counts),
        );
        Self::assemble(path, counts, mesh_side?, records_side?)
    }

    /// Makes the hierarchy of what the two sides read, after checking them against each
    /// other.
    fn assemble(
        path: &Path,
        counts: (usize, usize),
        (meta, mut mesh, labels): (meta::Meta, crate::mesh::Mesh, mesh::Labels),
        (records, placements, details, marks, rests): RecordSide,
    ) -> Result<Self> {
        let (nv, n) = (mesh.vertex_slots(), records.len());
        if (nv, mesh.halfedge_slots()) != counts {
            // Only a file changed while it was read (the counts are read twice).
            return Err(format_error(
                path,
                "section MESH: the slot counts changed while the file was read".into(),
            ));
        }
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
            return fail(
                "MARK",
                format!(
                    "{} vertex marks for {nv} vertex slots",
                    marks.of_vertex.len()
                ),
            );
        }
        if let Err(what) = check_records_against_level(&records, &mesh, meta.applied) {
            return fail("RECS", what);
        }

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
    // Section 1 is the mesh.
    let section = layout::sections(bytes, path)?[1];
    section.verify(path)?;
    mesh::read(&mut In::new(
        section.bytes,
        section.offset,
        section.tag,
        path,
    ))
}

/// Where the sections are read from: slices of the file in memory, or a reader at the
/// first of the sections about to be read (read in file order).
enum Sections<'a> {
    Slices(&'a [layout::Section<'a>]),
    Stream(&'a mut dyn std::io::Read, &'a [layout::Entry]),
}

impl Sections<'_> {
    /// A reader of section `k` (the next one, for a stream).
    fn open<'s>(&'s mut self, k: usize, path: &'s Path) -> In<'s> {
        match self {
            Sections::Slices(s) => In::new(s[k].bytes, s[k].offset, s[k].tag, path),
            Sections::Stream(reader, e) => {
                In::stream(&mut **reader, e[k].length, e[k].offset, e[k].tag, path)
            }
        }
    }
}

/// Sections `META`, `MESH` and `LABL`.
fn read_mesh_side(
    s: &mut Sections<'_>,
    path: &Path,
    (nv, _): (usize, usize),
) -> Result<(meta::Meta, crate::mesh::Mesh, mesh::Labels)> {
    let meta = meta::read(&mut s.open(0, path))?;
    let mesh = mesh::read(&mut s.open(1, path))?;
    let labels = mesh::read_labels(&mut s.open(2, path), nv)?;
    Ok((meta, mesh, labels))
}

/// What sections `RECS` to `REST` hold.
type RecordSide = (
    super::records::Records,
    super::placements::Placements,
    super::detail::Details,
    super::marks::Marks,
    Vec<super::rests::Rest>,
);

/// Sections `RECS`, `PLAC`, `DETL`, `MARK` and `REST`, their indices checked against the
/// mesh's slot counts `(nv, nh)`.
fn read_records_side(
    s: &mut Sections<'_>,
    path: &Path,
    (nv, nh): (usize, usize),
) -> Result<RecordSide> {
    let records = records::read(&mut s.open(3, path), (nv, nh))?;
    let n = records.len();
    let placements = records::read_placements(&mut s.open(4, path), n)?;
    let details = details::read(&mut s.open(5, path), n, nv)?;
    let marks = edits::read_marks(&mut s.open(6, path))?;
    let rests = edits::read_rests(&mut s.open(7, path), n, nv)?;
    Ok((records, placements, details, marks, rests))
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
