//! Module `shape`: implementation arrives with its issue.
