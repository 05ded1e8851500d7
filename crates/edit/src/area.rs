//! Module `area`: implementation arrives with its issue.
