//! The baked scenes and catalogues the images include are generated, not committed:
//! stops with the command that writes them when they are missing.
fn main() {
    let stamp = std::path::Path::new("../baked/BAKED");
    println!("cargo:rerun-if-changed={}", stamp.display());
    assert!(
        stamp.exists(),
        "boards/baked/ is not there: run `cargo xtask bake` first"
    );
}
