//! Module `smoothing`: implementation arrives with its issue.
