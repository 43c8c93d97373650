//! Puts the memory map (`memory/`) where the linker finds it as `memory.x` and links with cortex-m-rt's `link.x`.
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    // The low-RAM image links with 64 KiB of RAM. (No `memory.x` lies in this
    // directory: the linker would take it before the one in OUT_DIR.)
    let memory = if std::env::var_os("CARGO_FEATURE_RAM64K").is_some() {
        "memory/mps2-64k.x"
    } else {
        "memory/mps2.x"
    };
    std::fs::copy(memory, out.join("memory.x")).expect("memory/ is next to build.rs");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-link-arg=-Tlink.x");
    // Built for ARMv6-M, the image runs on mps2-an385 and names itself so.
    println!("cargo:rustc-check-cfg=cfg(armv6m)");
    if std::env::var("TARGET").is_ok_and(|t| t.starts_with("thumbv6m")) {
        println!("cargo:rustc-cfg=armv6m");
    }
}
