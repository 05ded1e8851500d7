//! What the command line prints: a human-readable text on stdout, or with `--json` one
//! JSON object; progress bars on stderr for long steps (never with `--quiet` or
//! `--json`).

use multires::progress::Bars;

/// Where and how a subcommand reports.
pub struct Output {
    /// No progress bars, no text beyond the result.
    pub quiet: bool,
    /// One JSON object on stdout instead of text.
    pub json: bool,
}

impl Output {
    pub fn new(quiet: bool, json: bool) -> Self {
        Self { quiet, json }
    }

    /// Progress bars, shown when `large` (a large mesh or a long batch) and neither
    /// `--quiet` nor `--json` was given.
    pub fn bars(&self, large: bool) -> Bars {
        Bars::new(large && !self.quiet && !self.json)
    }

    /// Prints the text report (not with `--json`).
    pub fn text(&self, text: impl AsRef<str>) {
        if !self.json {
            println!("{}", text.as_ref().trim_end());
        }
    }

    /// Prints the JSON report (with `--json`).
    pub fn json(&self, value: serde_json::Value) {
        if self.json {
            println!("{value}");
        }
    }
}
