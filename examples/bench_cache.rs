//! Prepares the large bench inputs of `benches/common` ahead of `cargo bench`: the shared
//! meshes subdivided 1-to-4 to about 1, 2, 4, 6 and 18 million faces, written once into
//! `bench-cache/` as binary PLY (regenerated when the source mesh is newer), with a
//! progress bar per mesh, then prints each file's size and face count.
//!
//! ```text
//! cargo run --release --example bench_cache            # every size
//! cargo run --release --example bench_cache -- 1M 2M   # some sizes
//! cargo run --release --example bench_cache -- 50M     # fandisk ×6, 53 M faces (1.3 GB)
//! cargo run --release --example bench_cache -- --list  # what would be made, and where
//! ```

use testkit::bench as common;

use std::time::Instant;

use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};

/// Generate the large bench meshes into bench-cache/.
#[derive(Parser, Debug)]
#[command(about)]
struct Args {
    /// Sizes to prepare (1M, 2M, 4M, 6M, 18M, and 50M only when named); default: all
    /// but 50M.
    sizes: Vec<String>,
    /// Only list the inputs, their files and whether they are up to date.
    #[arg(long)]
    list: bool,
}

fn main() {
    let args = Args::parse();
    let inputs = match common::select(&args.sizes) {
        Ok(inputs) => inputs,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    if args.list {
        for input in &inputs {
            println!(
                "{:<3} {:<36} {} ({})",
                input.label,
                input.name(),
                input.path().display(),
                if input.is_fresh() {
                    "cached"
                } else {
                    "to make"
                }
            );
        }
        return;
    }
    let style = ProgressStyle::with_template("{prefix:>3} [{bar:30}] {elapsed:>4} {msg}")
        .expect("valid template")
        .progress_chars("=> ");
    for input in &inputs {
        // steps: read, one per subdivision, write
        let bar = ProgressBar::new(input.subdivisions as u64 + 2)
            .with_style(style.clone())
            .with_prefix(input.label);
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        let clock = Instant::now();
        let path = input.prepare(&mut |step| match step {
            common::Step::Cached => bar.set_message("up to date"),
            common::Step::Reading => bar.set_message(format!("reading {}", input.source)),
            common::Step::Subdividing { done, total, faces } => {
                bar.set_position(done as u64);
                bar.set_message(format!(
                    "subdivided {done}/{total}: {} faces",
                    common::thousands(faces)
                ));
            }
            common::Step::Writing => {
                bar.set_position(input.subdivisions as u64 + 1);
                bar.set_message(format!("writing {}", input.path().display()));
            }
        });
        bar.finish_and_clear();
        let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        println!(
            "{:<3} {:<36} {:>7.1} MB  {}  ({:.1} s)",
            input.label,
            input.name(),
            bytes as f64 / 1e6,
            path.display(),
            clock.elapsed().as_secs_f64()
        );
    }
}
