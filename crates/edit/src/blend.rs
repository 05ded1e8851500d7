//! Module `blend`: implementation arrives with its issue.
