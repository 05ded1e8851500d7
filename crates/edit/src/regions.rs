//! Module `regions`: implementation arrives with its issue.
