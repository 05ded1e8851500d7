//! Module `mba`: implementation arrives with its issue.
