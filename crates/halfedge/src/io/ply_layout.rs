//! What both PLY readers share: the polygon soup they fill, the layout of the header they
//! agreed on, and the checked pushes of faces and triangle strips.

use std::path::Path;

use glam::DVec3;
use ply_rs_bw::ply::{ElementDef, PropertyType, ScalarType};

use crate::build::{BuildReport, PolygonBlock};
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Indexed polygons as read from a file, before building. They are kept in blocks of
/// about a megabyte (each ending at a polygon's end), which building frees one by one as
/// their faces go into the mesh.
#[derive(Debug, Default)]
pub(crate) struct PolygonSoup {
    pub(crate) positions: Vec<DVec3>,
    /// The blocks filled so far.
    full: Vec<PolygonBlock>,
    /// The block being filled.
    block: PolygonBlock,
}

impl PolygonSoup {
    /// An empty soup with room for `vertices` positions (at most a million reserved
    /// ahead: the count comes from a header).
    pub(crate) fn with_vertex_capacity(vertices: usize) -> Self {
        Self {
            positions: Vec::with_capacity(vertices.min(1 << 20)),
            ..Self::default()
        }
    }

    /// Indices per block (4 MB).
    pub(crate) const BLOCK: usize = 1 << 20;

    /// Appends a polygon.
    pub(crate) fn push_polygon(&mut self, polygon: impl IntoIterator<Item = u32>) {
        let start = self.len();
        for index in polygon {
            self.push(index);
        }
        self.end_polygon(start);
    }

    /// Number of indices in the block being filled: a polygon's start, for
    /// [`end_polygon`](Self::end_polygon).
    pub(crate) fn len(&self) -> usize {
        self.block.indices.len()
    }

    /// Appends one index of the polygon being read.
    pub(crate) fn push(&mut self, index: u32) {
        if self.block.indices.capacity() == 0 {
            self.block.indices.reserve_exact(Self::BLOCK + 64);
        }
        self.block.indices.push(index);
    }

    /// Records that the polygon starting at `start` (a former [`len`](Self::len)) ends
    /// at the last index pushed; starts a new block once this one is full.
    fn end_polygon(&mut self, start: usize) {
        self.block.end_polygon(start);
        if self.block.indices.len() >= Self::BLOCK {
            self.full.push(std::mem::take(&mut self.block));
        }
    }

    /// Builds the mesh; builder errors are turned into format errors naming the file.
    pub(crate) fn build(self, path: &Path) -> Result<(Mesh, BuildReport)> {
        let format = |message: String| Error::Format {
            path: path.to_owned(),
            message,
        };
        if self.positions.is_empty() {
            return Err(format("no vertices (the vertex element is empty)".into()));
        }
        let mut blocks = self.full;
        blocks.push(self.block);
        Mesh::from_polygon_blocks(self.positions, blocks).map_err(|e| match e {
            Error::IndexOutOfRange {
                face,
                index,
                vertex_count,
            } => format(format!(
                "face {face} refers to vertex {index}, but the file has {vertex_count} vertices"
            )),
            Error::NonFiniteCoordinate { vertex, value } => format(format!(
                "vertex {vertex} has a non-finite coordinate ({value})"
            )),
            other => other,
        })
    }
}

/// The two face-like elements the reader understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FaceKind {
    /// `face`: one polygon per element.
    Polygons,
    /// `tristrips`: strips separated by `-1`.
    Strips,
}

/// What the header says about the elements the reader uses.
pub(crate) struct Layout {
    pub(crate) n_vertices: usize,
}

/// Name of the index list property of a face-like element (`vertex_indices`, or
/// `vertex_index` as some writers name it).
pub(crate) fn index_property(
    element: &ElementDef,
) -> std::result::Result<Option<&'static str>, String> {
    let mut found = None;
    for name in ["vertex_indices", "vertex_index"] {
        match element.properties.get(name).map(|p| &p.data_type) {
            Some(PropertyType::List(..)) => {
                if found.is_some() {
                    return Err(format!(
                        "the {} element has both 'vertex_indices' and 'vertex_index'",
                        element.name
                    ));
                }
                found = Some(name);
            }
            Some(PropertyType::Scalar(_)) => {
                return Err(format!(
                    "{} property '{name}' is a number, expected a list",
                    element.name
                ))
            }
            None => {}
        }
    }
    Ok(found)
}

pub(super) fn is_integer(t: &ScalarType) -> bool {
    !matches!(t, ScalarType::Float | ScalarType::Double)
}

/// Checks a face's indices and appends it to the soup.
pub(crate) fn push_face(
    soup: &mut PolygonSoup,
    indices: impl Iterator<Item = i64>,
    face: usize,
    n_vertices: usize,
    format: &dyn Fn(String) -> Error,
) -> Result<()> {
    let start = soup.len();
    for index in indices {
        soup.push(check_index(index, n_vertices, "face", face, format)?);
    }
    soup.end_polygon(start);
    Ok(())
}

/// Turns one `tristrips` list into triangles (see the [module docs](self)).
pub(crate) fn push_strip(
    soup: &mut PolygonSoup,
    indices: impl Iterator<Item = i64>,
    element: usize,
    n_vertices: usize,
    format: &dyn Fn(String) -> Error,
) -> Result<()> {
    // (a, b): the previous two indices of the current strip; k: triangles so far in it.
    let mut window: [u32; 2] = [0; 2];
    let mut len = 0usize;
    for index in indices {
        if index == -1 {
            len = 0;
            continue;
        }
        let c = check_index(index, n_vertices, "tristrips", element, format)?;
        if len >= 2 {
            let [a, b] = window;
            // Triangle k = len - 2 of the strip: even ones (a, b, c), odd ones (b, a, c).
            let triangle = if (len - 2) % 2 == 0 {
                [a, b, c]
            } else {
                [b, a, c]
            };
            if a != b && b != c && a != c {
                soup.push_polygon(triangle);
            }
        }
        window = [window[1], c];
        len += 1;
    }
    Ok(())
}

fn check_index(
    index: i64,
    n_vertices: usize,
    element: &str,
    number: usize,
    format: &dyn Fn(String) -> Error,
) -> Result<u32> {
    if index < 0 {
        return Err(format(format!(
            "{element} {number} has a negative vertex index ({index})"
        )));
    }
    if index as u64 >= n_vertices as u64 {
        return Err(format(format!(
            "{element} {number} refers to vertex {index}, but the file has {n_vertices} vertices"
        )));
    }
    Ok(index as u32)
}
