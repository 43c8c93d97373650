//! The `fixshade` command; see `fixshade help`.

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match fixshade_sim::cli::run(&args) {
        Ok(out) => println!("{out}"),
        Err(e) => {
            eprintln!("fixshade: {}", e.message);
            std::process::exit(e.code);
        }
    }
}
