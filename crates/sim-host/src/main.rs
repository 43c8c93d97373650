//! The `fixshade` command; see `fixshade help`.

use std::io::Write;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match fixshade_sim::cli::run(&args) {
        // A closed pipe (`fixshade list | head -1`) is not an error worth a panic.
        Ok(out) => {
            let _ = writeln!(std::io::stdout(), "{out}");
        }
        Err(e) => {
            eprintln!("fixshade: {}", e.message);
            std::process::exit(e.code);
        }
    }
}
