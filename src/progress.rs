//! What long jobs report while they run. The libraries never print; the jobs of this
//! crate ([`crate::workflow`], [`crate::batch`], loading) tell a [`Progress`] what they are
//! doing, and the command line and the examples draw it (with the `cli` feature,
//! [`Bars`]: spinners and bars from `indicatif` on stderr, silent when stderr is not a
//! terminal).

/// Receives a job's progress. Every method has a default that does nothing, so an
/// implementation picks what it shows; [`Silent`] shows nothing.
pub trait Progress: Send {
    /// A step starts: `what` it does, and its `total` amount of work when known (faces to
    /// remove, levels to refine, files to process), for a bar; `None` for a spinner.
    fn start(&mut self, what: &str, total: Option<u64>) {
        let _ = (what, total);
    }
    /// The current step has done `done` of its total (see [`start`](Self::start)), with
    /// an optional short `message` (the level reached, …).
    fn advance(&mut self, done: u64, message: &str) {
        let _ = (done, message);
    }
    /// The current step is over.
    fn finish(&mut self) {}
}

/// Shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {}

/// Runs `f` as one step of `progress` (a spinner saying `what`), and ends the step.
pub fn step<T>(progress: &mut dyn Progress, what: &str, f: impl FnOnce() -> T) -> T {
    progress.start(what, None);
    let result = f();
    progress.finish();
    result
}

/// Meshes with more faces than this get progress displays from the command line and the
/// examples (smaller jobs are over before a bar would be read).
pub const LARGE_FACES: usize = 200_000;

/// Mesh files bigger than this (bytes) get a spinner while loading: about 200k faces in
/// OBJ, 400k in binary PLY.
pub const LARGE_FILE_BYTES: u64 = 8 << 20;

#[cfg(feature = "cli")]
pub use bars::Bars;

#[cfg(feature = "cli")]
mod bars {
    use std::time::Duration;

    use indicatif::{ProgressBar, ProgressStyle};

    use super::Progress;

    /// Spinners and bars from `indicatif` on stderr (silent when stderr is not a
    /// terminal, or when made [`hidden`](Bars::hidden)).
    #[derive(Debug)]
    pub struct Bars {
        show: bool,
        bar: Option<ProgressBar>,
    }

    impl Bars {
        /// Bars shown when `show` (the command line shows them for large meshes and long
        /// batches, and never with `--quiet`).
        #[must_use]
        pub fn new(show: bool) -> Self {
            Self { show, bar: None }
        }

        /// Bars that show nothing.
        #[must_use]
        pub fn hidden() -> Self {
            Self::new(false)
        }

        /// Shows or hides the bars of the steps that start from now on.
        pub fn set_shown(&mut self, show: bool) {
            self.show = show;
        }
    }

    impl Progress for Bars {
        fn start(&mut self, what: &str, total: Option<u64>) {
            self.finish();
            if !self.show {
                return;
            }
            let bar = match total {
                Some(len) => ProgressBar::new(len).with_style(
                    ProgressStyle::with_template("{msg:30} [{bar:40}] {pos}/{len} {elapsed}")
                        .unwrap_or_else(|_| ProgressStyle::default_bar())
                        .progress_chars("=> "),
                ),
                None => {
                    let bar = ProgressBar::new_spinner().with_style(
                        ProgressStyle::with_template("{spinner} {msg} {elapsed}")
                            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
                    );
                    bar.enable_steady_tick(Duration::from_millis(120));
                    bar
                }
            };
            bar.set_message(what.to_owned());
            self.bar = Some(bar);
        }

        fn advance(&mut self, done: u64, message: &str) {
            if let Some(bar) = &self.bar {
                bar.set_position(done);
                if !message.is_empty() {
                    bar.set_message(message.to_owned());
                }
            }
        }

        fn finish(&mut self) {
            if let Some(bar) = self.bar.take() {
                bar.finish_and_clear();
            }
        }
    }

    impl Drop for Bars {
        fn drop(&mut self) {
            self.finish();
        }
    }
}
