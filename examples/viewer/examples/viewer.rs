//! `cargo run --release --example viewer -- [FILE] [--script S.json] [--screenshot OUT.png]`:
//! the interactive viewer (see the `viewer` crate docs).

fn main() {
    viewer::main()
}
