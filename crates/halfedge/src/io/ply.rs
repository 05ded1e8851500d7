//! PLY input: ASCII, binary little and big endian.
//!
//! The header is parsed by `ply-rs-bw`. From it the reader picks
//! - the `vertex` element: scalar properties `x`, `y`, `z` of any numeric type (other
//!   properties such as normals or colours are skipped);
//! - the `face` element: the list property `vertex_indices` (or `vertex_index`) with any
//!   integer count and index types; polygons are fan-triangulated by the builder;
//! - the `tristrips` element that some scanners write: list property `vertex_indices`,
//!   strips separated by `-1`, every other triangle reversed so that all keep the strip's
//!   orientation; degenerate stitching triangles (a repeated index) are left out before
//!   building, so they are not counted as dropped faces;
//! - every other element and property is skipped.
//!
//! The payload is then read on one of two routes:
//! - the **fast route** (module `ply_fast`) for binary files whose `vertex` element has
//!   only scalar properties and whose `face` / `tristrips` elements have the index list
//!   as their only property, which is how almost every binary PLY is laid out. It
//!   decodes the bytes straight from a read buffer. `ply-rs-bw` builds one `Vec` per
//!   face and dispatches every value through a property-name lookup, which made loading
//!   a 1.6-million-face binary PLY slower than OpenMesh's reader (see `ply_fast`);
//! - the **general route** through `ply-rs-bw`'s typed [`PropertyAccess`] (own element
//!   structs, no `HashMap` per element) for ASCII files and every other layout.
//!
//! Both routes check everything: truncated payloads, negative or out-of-range indices,
//! non-finite coordinates and malformed headers are [`Error::Format`] errors naming the
//! file, the element and the position; nothing panics.

use std::io::{BufRead, BufReader, ErrorKind, Read};
use std::path::Path;

use glam::DVec3;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    BeginList, ElementDef, Header, PropertyAccess, PropertyAccessResult, PropertyType,
};

use super::ply_fast;
use super::ply_layout::{
    index_property, is_integer, push_face, push_strip, FaceKind, Layout, PolygonSoup,
};
use crate::build::BuildReport;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Reads a PLY file (ASCII, binary little or big endian). Vertex `i` of the file is the
/// vertex with [`Mesh::vertex_index`] `i`; see the [module docs](self) for what is read.
/// The file is streamed, not read into memory first.
pub fn read_ply(path: impl AsRef<Path>) -> Result<(Mesh, BuildReport)> {
    let path = path.as_ref();
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: path.to_owned(),
        source,
    })?;
    let soup = read_ply_soup(BufReader::with_capacity(1 << 16, file), path)?;
    soup.build(path)
}

/// Reads PLY data from memory; `path` is only used in error messages.
pub fn read_ply_from_bytes(bytes: &[u8], path: &Path) -> Result<(Mesh, BuildReport)> {
    let soup = read_ply_soup(bytes, path)?;
    soup.build(path)
}

/// Checks the header: a `vertex` element with scalar `x`, `y`, `z`, and index lists of
/// integer type in `face` / `tristrips`.
fn check_header(header: &Header, format: &dyn Fn(String) -> Error) -> Result<Layout> {
    let vertex = header
        .elements
        .get("vertex")
        .ok_or_else(|| format("the header has no 'vertex' element".into()))?;
    for axis in ["x", "y", "z"] {
        match vertex.properties.get(axis).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List(..)) => {
                return Err(format(format!(
                    "vertex property '{axis}' is a list, expected a number"
                )))
            }
            None => {
                return Err(format(format!(
                    "the vertex element has no '{axis}' property"
                )))
            }
        }
    }
    for name in ["face", "tristrips"] {
        let Some(element) = header.elements.get(name) else {
            continue;
        };
        let property = index_property(element).map_err(&format)?;
        if let Some(property) = property {
            if let PropertyType::List(count, item) = &element.properties[property].data_type {
                if !is_integer(count) || !is_integer(item) {
                    return Err(format(format!(
                        "{name} property '{property}' must be a list of integers, found list {count:?} {item:?}"
                    )));
                }
            }
        } else if element.count > 0 {
            return Err(format(format!(
                "the {name} element has no 'vertex_indices' list"
            )));
        }
    }
    Ok(Layout {
        n_vertices: vertex.count,
    })
}

/// Parses the header and the payload into a polygon soup.
pub(crate) fn read_ply_soup<R: BufRead>(mut input: R, path: &Path) -> Result<PolygonSoup> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let io = |source: std::io::Error| Error::Io {
        path: path.to_owned(),
        source,
    };
    if input.fill_buf().map_err(io)?.is_empty() {
        return Err(format("line 1: empty file".into()));
    }
    let header_text = readable_header(&mut input).map_err(io)?;
    let mut reader = Reader::new(std::io::Cursor::new(header_text).chain(input));
    let header = Parser::<SkippedElement>::new()
        .read_header(&mut reader)
        .map_err(|e| {
            // Errors of the line reader (text that is not UTF-8) carry no line: the
            // parser's line is the one it was reading.
            // (The header's own checks after its last line say where they stopped: on
            // the line after `end_header`.)
            let line = e.line().unwrap_or(match e.kind() {
                ErrorKind::InvalidInput => reader.line().saturating_sub(1).max(1),
                _ => reader.line().max(1),
            });
            let message = e.to_string();
            let message = message
                .strip_prefix(&format!("Line {line}: "))
                .unwrap_or(&message);
            format(format!("line {line}: malformed PLY header: {message}"))
        })?;
    // What is wrong with the header as a whole is reported at its last line.
    let end_header = reader.line().saturating_sub(1).max(1);
    let in_header = |message: String| format(format!("line {end_header} (end_header): {message}"));
    let layout = check_header(&header, &in_header)?;
    if layout.n_vertices == 0 {
        return Err(in_header(
            "no vertices (the vertex element is empty)".into(),
        ));
    }
    if let Some(plans) = ply_fast::plans(&header) {
        return ply_fast::read_binary(&header, &plans, reader.get_mut(), &layout, path);
    }
    read_general(&header, reader, &layout, path)
}

/// The most header bytes read ahead of the parser (a header is a few hundred bytes; a
/// file whose first 16 MiB hold no `end_header` is handed to the parser as it is, which
/// refuses it).
const MAX_HEADER_BYTES: usize = 1 << 24;

/// The header's lines up to and including `end_header`, with bytes that are not UTF-8
/// replaced (`ply-rs-bw` reads header lines as UTF-8 text: a Latin-1 `comment` or
/// `obj_info` would refuse a readable file). Lines keep their numbers, so the parser's
/// errors still name the file's line; a replaced byte anywhere but in a comment makes the
/// line malformed, as it was.
fn readable_header<R: BufRead>(input: &mut R) -> std::io::Result<Vec<u8>> {
    let mut header = Vec::new();
    let mut line = Vec::new();
    while header.len() < MAX_HEADER_BYTES {
        line.clear();
        if input.read_until(b'\n', &mut line)? == 0 {
            break;
        }
        match String::from_utf8_lossy(&line) {
            std::borrow::Cow::Borrowed(_) => header.extend_from_slice(&line),
            std::borrow::Cow::Owned(text) => header.extend_from_slice(text.as_bytes()),
        }
        if line.trim_ascii() == b"end_header" {
            break;
        }
    }
    Ok(header)
}

/// The general route: `ply-rs-bw` with own element structs.
fn read_general<R: BufRead>(
    header: &Header,
    mut reader: Reader<R>,
    layout: &Layout,
    path: &Path,
) -> Result<PolygonSoup> {
    let format = |message: String| Error::Format {
        path: path.to_owned(),
        message,
    };
    let format = &format;
    // The declared count is not trusted for allocation (the vector grows as vertices are
    // actually read).
    let mut soup = PolygonSoup::with_vertex_capacity(layout.n_vertices);
    let ascii = header.encoding == ply_rs_bw::ply::Encoding::Ascii;
    // `first`: the parser's line when the element started (ply-rs-bw counts one "line"
    // per element in binary files too); errors of the line reader carry no line, the
    // parser's is the one it was reading.
    let payload_error =
        |element: &ElementDef, first: usize, now: usize, e: ply_rs_bw::parser::ParseError| {
            let what = match e.kind() {
                ErrorKind::UnexpectedEof => "truncated file",
                ErrorKind::InvalidInput | ErrorKind::InvalidData => "malformed data",
                _ => {
                    return Error::Io {
                        path: path.to_owned(),
                        source: e.into(),
                    }
                }
            };
            let line = e.line().unwrap_or(now);
            let message = e.to_string();
            let message = message
                .strip_prefix(&format!("Line {line}: "))
                .unwrap_or(&message);
            let number = line.saturating_sub(first);
            let place = if ascii {
                format!("line {line}, {} {number}", element.name)
            } else {
                format!("{} {number}", element.name)
            };
            format(format!(
                "{place}: {what} in element '{}' ({} declared): {message}",
                element.name, element.count
            ))
        };
    for (name, element) in &header.elements {
        // The parser's line when the element starts (after the header: the line after
        // `end_header`).
        let first = reader.line();
        match name.as_str() {
            "vertex" => {
                let vertices = Parser::<PlyVertex>::new()
                    .read_payload_for_element(&mut reader, element, header)
                    .map_err(|e| payload_error(element, first, reader.line(), e))?;
                soup.positions
                    .extend(vertices.iter().map(|v| DVec3::from_array(v.0)));
            }
            "face" | "tristrips" => {
                let kind = if name == "face" {
                    FaceKind::Polygons
                } else {
                    FaceKind::Strips
                };
                let faces = Parser::<PlyIndexList>::new()
                    .read_payload_for_element(&mut reader, element, header)
                    .map_err(|e| payload_error(element, first, reader.line(), e))?;
                for (i, face) in faces.iter().enumerate() {
                    let indices = face.indices();
                    match kind {
                        FaceKind::Polygons => {
                            push_face(&mut soup, indices, i, layout.n_vertices, format)?
                        }
                        FaceKind::Strips => {
                            push_strip(&mut soup, indices, i, layout.n_vertices, format)?
                        }
                    }
                }
            }
            _ => {
                Parser::<SkippedElement>::new()
                    .read_payload_for_element(&mut reader, element, header)
                    .map_err(|e| payload_error(element, first, reader.line(), e))?;
            }
        }
    }
    Ok(soup)
}

/// A vertex of the general route: only `x`, `y`, `z` are kept.
struct PlyVertex([f64; 3]);

impl PlyVertex {
    #[inline]
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return PropertyAccessResult::Ignored,
        };
        self.0[axis] = value;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        Self([0.0; 3])
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, value.into())
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// A face or strip of the general route: the index list. `int` and `uint` lists (the
/// usual ones) are filled in place by the parser; the narrow integer types go through
/// the setters and are widened to `i64`. Only one of the three is non-empty.
#[derive(Default)]
struct PlyIndexList {
    int: Vec<i32>,
    uint: Vec<u32>,
    narrow: Vec<i64>,
}

impl PlyIndexList {
    /// The indices, widened to `i64` so that negative ones are seen and reported.
    fn indices(&self) -> impl Iterator<Item = i64> + '_ {
        let int = self.int.iter().map(|&i| i64::from(i));
        let uint = self.uint.iter().map(|&i| i64::from(i));
        int.chain(uint).chain(self.narrow.iter().copied())
    }
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

macro_rules! narrow_index_list_setter {
    ($($method:ident: $t:ty),*) => {$(
        fn $method(&mut self, name: &str, value: Vec<$t>) -> PropertyAccessResult {
            if !is_index_list(name) {
                return PropertyAccessResult::Ignored;
            }
            self.narrow.clear();
            self.narrow.extend(value.into_iter().map(i64::from));
            PropertyAccessResult::Set
        }
    )*};
}

impl PropertyAccess for PlyIndexList {
    fn new() -> Self {
        Self::default()
    }
    narrow_index_list_setter!(set_list_char: i8, set_list_uchar: u8, set_list_short: i16,
        set_list_ushort: u16);
    fn begin_list_int(&mut self, name: &str, _len: usize) -> BeginList<'_, i32> {
        if is_index_list(name) {
            BeginList::Fill(&mut self.int)
        } else {
            BeginList::UseSetter
        }
    }
    fn begin_list_uint(&mut self, name: &str, _len: usize) -> BeginList<'_, u32> {
        if is_index_list(name) {
            BeginList::Fill(&mut self.uint)
        } else {
            BeginList::UseSetter
        }
    }
}

/// An element the reader does not use: every property is read and dropped.
struct SkippedElement;

impl PropertyAccess for SkippedElement {
    fn new() -> Self {
        Self
    }
}
