//! PLY output through `ply-rs-bw` (the maintained fork: `ply-rs` 0.1.3 writes corrupt
//! binary PLY whenever faces are present).
//!
//! The file has a `vertex` element with `double` properties `x`, `y`, `z` (positions are
//! written at full precision: binary files hold the very bits, ASCII files the shortest
//! decimal that parses back to the same `f64`) and a `face` element with the list property
//! `vertex_indices` (`uchar` count, `int` indices). Live vertices are written compacted, in
//! [`Mesh::vertices`] order: see [`file_vertex_indices`](super::file_vertex_indices).

use std::io::Write;
use std::path::Path;

use ply_rs_bw::ply::{
    Addable, ElementDef, Encoding, Header, PropertyAccess, PropertyDef, PropertyType, ScalarType,
};
use ply_rs_bw::writer::Writer;

use crate::error::{Error, Result};

use crate::mesh::Mesh;

/// The PLY encodings the writer produces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PlyFormat {
    /// Text; positions as shortest round-trip decimals.
    Ascii,
    /// Binary, little endian (the common binary PLY).
    #[default]
    BinaryLittleEndian,
    /// Binary, big endian (rare; offered mainly to test readers).
    BinaryBigEndian,
}

impl PlyFormat {
    fn encoding(self) -> Encoding {
        match self {
            Self::Ascii => Encoding::Ascii,
            Self::BinaryLittleEndian => Encoding::BinaryLittleEndian,
            Self::BinaryBigEndian => Encoding::BinaryBigEndian,
        }
    }
}

/// Writes a mesh as PLY in the given encoding (see the [module docs](self)).
pub fn write_ply(path: impl AsRef<Path>, mesh: &Mesh, format: PlyFormat) -> Result<()> {
    let path = path.as_ref();
    super::write_file(path, |out| write_ply_to(out, mesh, format))
}

/// Writes a mesh as PLY into any writer (see the [module docs](self)). Returns an
/// [`Error::InvalidArgument`] if the mesh has more vertices than `int` indices can
/// address, and [`Error::Io`] (with an empty path) if writing fails.
pub fn write_ply_to(out: &mut impl Write, mesh: &Mesh, format: PlyFormat) -> Result<()> {
    if mesh.n_vertices() > i32::MAX as usize {
        return Err(Error::InvalidArgument(format!(
            "{} vertices do not fit PLY int indices",
            mesh.n_vertices()
        )));
    }
    let io = |source: std::io::Error| Error::Io {
        path: Default::default(),
        source,
    };
    let header = header(mesh, format);
    let vertex_def = &header.elements["vertex"];
    let face_def = &header.elements["face"];
    let vertex_writer = Writer::<VertexOut>::new();
    let face_writer = Writer::<FaceOut>::new();
    vertex_writer.write_header(out, &header).map_err(io)?;

    for v in mesh.vertices() {
        let vertex = VertexOut(mesh.position(v).to_array());
        write_element(&vertex_writer, out, &vertex, vertex_def, format).map_err(io)?;
    }

    let index = super::file_vertex_indices(mesh);
    for f in mesh.faces() {
        let triangle = mesh.triangle(f).map(|v| index[mesh.vertex_index(v)] as i32);
        write_element(&face_writer, out, &FaceOut(triangle), face_def, format).map_err(io)?;
    }
    out.flush().map_err(io)
}

fn write_element<W: Write, E: PropertyAccess>(
    writer: &Writer<E>,
    out: &mut W,
    element: &E,
    def: &ElementDef,
    format: PlyFormat,
) -> std::io::Result<usize> {
    match format {
        PlyFormat::Ascii => writer.write_ascii_element(out, element, def),
        PlyFormat::BinaryLittleEndian => writer.write_little_endian_element(out, element, def),
        PlyFormat::BinaryBigEndian => writer.write_big_endian_element(out, element, def),
    }
}

fn header(mesh: &Mesh, format: PlyFormat) -> Header {
    let mut header = Header::new();
    header.encoding = format.encoding();
    header
        .comments
        .push("written by multires (halfedge crate)".into());
    let mut vertex = ElementDef::new("vertex".into());
    vertex.count = mesh.n_vertices();
    for axis in ["x", "y", "z"] {
        vertex.properties.add(PropertyDef::new(
            axis.into(),
            PropertyType::Scalar(ScalarType::Double),
        ));
    }
    let mut face = ElementDef::new("face".into());
    face.count = mesh.n_faces();
    face.properties.add(PropertyDef::new(
        "vertex_indices".into(),
        PropertyType::List(ScalarType::UChar, ScalarType::Int),
    ));
    header.elements.add(vertex);
    header.elements.add(face);
    header
}

/// A vertex as the writer sees it.
struct VertexOut([f64; 3]);

impl PropertyAccess for VertexOut {
    fn new() -> Self {
        Self([0.0; 3])
    }
    fn get_double(&self, name: &str) -> Option<f64> {
        match name {
            "x" => Some(self.0[0]),
            "y" => Some(self.0[1]),
            "z" => Some(self.0[2]),
            _ => None,
        }
    }
}

/// A triangle as the writer sees it (file vertex numbers).
struct FaceOut([i32; 3]);

impl PropertyAccess for FaceOut {
    fn new() -> Self {
        Self([0; 3])
    }
    fn get_list_int(&self, name: &str) -> Option<&[i32]> {
        (name == "vertex_indices").then_some(&self.0[..])
    }
}
