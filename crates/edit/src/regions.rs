//! Regions (placeholder while building).

/// Which region.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RegionKind {
    /// Handle.
    Handle,
    /// Fixed.
    Fixed,
    /// Deformable.
    Deformable,
}
impl std::fmt::Display for RegionKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Handle => "handle",
            Self::Fixed => "fixed",
            Self::Deformable => "deformable",
        })
    }
}
