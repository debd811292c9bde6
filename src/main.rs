//! The `satflock` command-line tool: a thin layer over the library's public API.
fn main() {
    println!("satflock {}", env!("CARGO_PKG_VERSION"));
}
