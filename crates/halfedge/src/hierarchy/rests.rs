//! Where the vertices were before the edits: the copies refinement interpolates the
//! edits' motion from.

use crate::mesh::Mesh;

/// The positions edits started from, for refinement to interpolate the edits' motion
/// ([`DetailMode::LocalFrame`]): a copy of every live vertex's position taken when
/// [`Hierarchy::mesh_mut`] hands out the mesh, kept up to date by the splits of the
/// records it serves (each puts its recorded positions in). It serves the records
/// `floor..ceil`, whose neighbourhoods were at these positions when they were collapsed:
/// those collapsed since the previous edit, up to the level it was taken at; a collapse
/// (which takes the current positions into its record) ends the range below itself.
#[derive(Clone, Debug)]
pub(super) struct Rest {
    pub(super) positions: Vec<[f64; 3]>,
    pub(super) floor: usize,
    pub(super) ceil: usize,
    /// The splits of records `synced..ceil` have put their positions in (the others are
    /// put in when a split first needs the copy: a refinement whose every survivor moved
    /// with its neighbours, a translation or rotation of the whole level, never does).
    pub(super) synced: usize,
    /// A split needed the copy: from then on every split puts its positions in.
    pub(super) active: bool,
    /// The vertex slots of the faces the edits themselves turned over at the level the
    /// copy was taken at (against the copy), noted when the first walk finer leaves that
    /// level (`None` before, or when refinement left it another way): their descendants
    /// are turned by the edit, not by the refinement, and the unfolding leaves them be.
    pub(super) turned_by_edit: Option<Vec<u32>>,
}

/// At most this many [`Rest`]s are kept (edits at levels walked coarser from one
/// another); records only older ones served fall back to the local frame alone.
pub(super) const MAX_RESTS: usize = 4;

impl Rest {
    /// The live vertices' positions of `mesh` (other slots zero, left untouched by the
    /// allocator: a coarse level of a large mesh costs its live vertices only).
    pub(super) fn take(mesh: &Mesh, floor: usize, ceil: usize) -> Self {
        let mut positions = vec![[0.0f64; 3]; mesh.vertex_slots()];
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            positions[i] = mesh.positions[i].to_array();
        }
        Self {
            positions,
            floor,
            ceil,
            synced: ceil,
            active: false,
            turned_by_edit: None,
        }
    }

    /// True when this copy serves record `r`.
    pub(super) fn serves(&self, r: usize) -> bool {
        (self.floor..self.ceil).contains(&r)
    }
}
