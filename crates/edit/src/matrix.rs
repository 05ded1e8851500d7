//! Module `matrix`: implementation arrives with its issue.
