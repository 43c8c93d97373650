//! The `fixshade` command; see `fixshade help`.

fn main() {
    fixshade_sim::cli::main()
}
