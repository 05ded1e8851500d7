//! Module `barr`: implementation arrives with its issue.
