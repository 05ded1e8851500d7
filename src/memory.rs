//! The process's peak memory, per step of a long job: the workflow's table reports the
//! resident set's high-water mark of each step beside its seconds.
//!
//! On Linux the kernel keeps the high-water mark (`VmHWM` in `/proc/self/status`) and
//! lets a process reset it to the current resident size (writing `5` to
//! `/proc/self/clear_refs`), so a step's peak is measured, not sampled. Elsewhere, or
//! where `/proc` is not mounted, both calls report that they could not (`None`, `false`)
//! and the tables leave the column empty.

/// The peak resident set size of this process in bytes since it started or since the
/// last successful [`reset_peak_resident`]; `None` where the platform does not say.
#[must_use]
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    kib.checked_mul(1024)
}

/// Sets the peak [`peak_resident_bytes`] reports back to the current resident size, so
/// that the next reading is the peak of what runs in between; `false` where the platform
/// cannot (the next reading is then the peak since an earlier reset or the start).
pub fn reset_peak_resident() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Measures the peak of a stretch of work: made at its start (resetting the peak), read
/// at its end.
#[derive(Debug)]
pub struct PeakMeter {
    reset: bool,
}

impl PeakMeter {
    /// Starts a stretch: resets the process's peak where the platform allows.
    #[must_use]
    pub fn start() -> Self {
        Self {
            reset: reset_peak_resident(),
        }
    }

    /// The peak resident size in bytes since [`start`](Self::start); `None` when the
    /// platform could not reset or report it.
    #[must_use]
    pub fn peak(&self) -> Option<u64> {
        if self.reset {
            peak_resident_bytes()
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On Linux the peak after a reset covers a large allocation touched in between and
    /// falls back below it after the next reset.
    #[test]
    #[cfg(target_os = "linux")]
    fn a_reset_peak_covers_what_was_touched_after_it() {
        let meter = PeakMeter::start();
        let Some(before) = meter.peak() else {
            return; // no /proc (a sandbox): nothing to measure
        };
        let big = vec![1u8; 256 << 20];
        std::hint::black_box(&big);
        let with = meter.peak().unwrap();
        assert!(with >= before + (200 << 20), "{before} -> {with}");
        drop(big);
        let meter = PeakMeter::start();
        let after = meter.peak().unwrap();
        assert!(after + (200 << 20) <= with, "{with} -> {after}");
    }
}
