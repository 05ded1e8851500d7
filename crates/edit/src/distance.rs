//! Module `distance`: implementation arrives with its issue.
