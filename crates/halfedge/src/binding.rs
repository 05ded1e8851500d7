//! What a value derived from a mesh was made for: a [`MeshBinding`] records the mesh
//! instance, its connectivity and, for the mesh of a [`Hierarchy`](crate::Hierarchy), the
//! level position it was at. Everything the edit crate derives from a mesh (editing areas,
//! sessions, sub-meshes, FFD attachments, …) keeps one and checks it on every use with
//! [`MeshBinding::check`], which refuses with one error, [`StaleBinding`], saying what was
//! made for which mesh and what it met.
//!
//! A binding fits the mesh it was made from while its connectivity is unchanged (positions
//! and attributes may change), and, in a hierarchy, whenever the hierarchy is back at the
//! same position by its own steps (walking to another level and back). It also fits a
//! clone of that mesh made since, until the clone's connectivity changes. Any other change
//! of connectivity, every level change, and any other mesh make the binding stale.

use crate::Mesh;

/// What a derived value was made for (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshBinding {
    mesh: u64,
    change: u64,
    level: Option<(u64, usize)>,
}

/// A value derived from a mesh met another mesh, or the same mesh at another level or
/// after its connectivity changed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} was made for {made} and met {met}: make it again from the mesh it is used on")]
pub struct StaleBinding {
    /// What was used (for example "the sub-mesh").
    pub what: &'static str,
    /// Where it was made, in words.
    pub made: String,
    /// What it met, in words.
    pub met: String,
}

impl MeshBinding {
    /// True when this binding fits `mesh` (see the [module docs](self)).
    #[inline]
    pub fn fits(&self, mesh: &Mesh) -> bool {
        let same_connectivity = self.change == mesh.stamp_count
            && (self.mesh == mesh.stamp_id
                || mesh
                    .lineage
                    .iter()
                    .any(|&(id, count)| id == self.mesh && count == self.change));
        same_connectivity
            || (self.mesh == mesh.stamp_id && self.level.is_some() && self.level == mesh.level_tag)
    }

    /// `Ok` when this binding fits `mesh`, else [`StaleBinding`] naming `what`.
    ///
    /// # Errors
    /// [`StaleBinding`] when the binding does not fit.
    pub fn check(&self, mesh: &Mesh, what: &'static str) -> Result<(), StaleBinding> {
        if self.fits(mesh) {
            return Ok(());
        }
        Err(StaleBinding {
            what,
            made: describe(self.mesh, self.change, self.level),
            met: describe(mesh.stamp_id, mesh.stamp_count, mesh.level_tag),
        })
    }
}

impl MeshBinding {
    /// `Ok` when `other` names the same mesh in the same state as this binding (two
    /// values derived from one mesh, checked against each other where the mesh itself is
    /// not at hand), else [`StaleBinding`] naming `what`.
    ///
    /// # Errors
    /// [`StaleBinding`] when the two bindings differ.
    pub fn check_same(&self, other: &MeshBinding, what: &'static str) -> Result<(), StaleBinding> {
        if self == other {
            return Ok(());
        }
        Err(StaleBinding {
            what,
            made: describe(other.mesh, other.change, other.level),
            met: format!(
                "a value made for {}",
                describe(self.mesh, self.change, self.level)
            ),
        })
    }
}

fn describe(mesh: u64, change: u64, level: Option<(u64, usize)>) -> String {
    match level {
        Some((hierarchy, applied)) => {
            format!("mesh #{mesh} in hierarchy #{hierarchy} with {applied} records collapsed")
        }
        None => format!("mesh #{mesh} after {change} connectivity changes"),
    }
}

impl Mesh {
    /// The binding of a value derived from this mesh now (see [`MeshBinding`]).
    #[inline]
    pub fn binding(&self) -> MeshBinding {
        MeshBinding {
            mesh: self.stamp_id,
            change: self.stamp_count,
            level: self.level_tag,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::generators;

    #[test]
    fn a_binding_fits_until_the_connectivity_changes() {
        let mut mesh = generators::icosphere(1);
        let b = mesh.binding();
        assert!(b.check(&mesh, "x").is_ok());
        let v = mesh.vertices().next().unwrap();
        let p = mesh.position(v);
        mesh.set_position(v, p * 2.0);
        assert!(b.fits(&mesh), "positions do not count");
        let mut clone = mesh.clone();
        assert!(
            b.fits(&clone),
            "a clone made since has the same connectivity"
        );
        let h = mesh.halfedges().next().unwrap();
        clone.collapse(h).unwrap();
        assert!(!b.fits(&clone), "until its own connectivity changes");
        assert!(
            !generators::icosphere(1).binding().fits(&mesh),
            "another mesh"
        );
        mesh.collapse(h).unwrap();
        assert!(!b.fits(&mesh.clone()), "a clone made after a change");
        let e = b.check(&mesh, "the thing").unwrap_err();
        assert!(
            e.to_string().contains("the thing was made for mesh #"),
            "{e}"
        );
    }
}
