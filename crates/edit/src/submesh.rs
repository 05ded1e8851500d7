//! Module `submesh`: implementation arrives with its issue.
