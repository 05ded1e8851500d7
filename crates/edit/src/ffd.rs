//! Module `ffd`: implementation arrives with its issue.
