//! Puts `memory.x` where the linker finds it; links with cortex-m-rt's `link.x` and
//! defmt's `defmt.x`; `--nmagic` keeps the sections unaligned to pages.
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::copy("memory.x", out.join("memory.x")).expect("memory.x is next to build.rs");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    // The baked teapot is generated, not committed (`cargo xtask bake`).
    let stamp = std::path::Path::new("../baked/BAKED");
    println!("cargo:rerun-if-changed={}", stamp.display());
    assert!(
        stamp.exists(),
        "boards/baked/ is not there: run `cargo xtask bake` first"
    );
    println!("cargo:rustc-link-arg=--nmagic");
    println!("cargo:rustc-link-arg=-Tlink.x");
    println!("cargo:rustc-link-arg=-Tdefmt.x");
}
