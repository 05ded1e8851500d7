//! The viewer binary (`cargo run --release -p viewer -- [FILE]`); the same program is the
//! example `viewer` (`cargo run --release --example viewer -- [FILE]`).

fn main() {
    viewer::main()
}
