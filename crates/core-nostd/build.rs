//! Names the instruction set the core is built for, as `cfg`s the arithmetic
//! chooses its cheapest exact form by (every form gives the same bits; tested):
//!
//! - `fixshade_v6m`: ARMv6-M (Cortex-M0/M0+): `MULS` is 32×32→32 only and there is
//!   no `CLZ`, so wide products are built from 16×16-bit ones
//!   (`math::mul_wide`) and leading zeros are counted by a short search.
//! - `fixshade_dsp`: ARMv7E-M (Cortex-M4/M7): the DSP extension (`SADD16`, `SEL`, …)
//!   for the span loops.
//!
//! Stable Rust does not expose ARM target features to `cfg`, so the target triple
//! decides.
fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-check-cfg=cfg(fixshade_v6m)");
    println!("cargo:rustc-check-cfg=cfg(fixshade_dsp)");
    let target = std::env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv6m") {
        println!("cargo:rustc-cfg=fixshade_v6m");
    }
    if target.starts_with("thumbv7em") {
        println!("cargo:rustc-cfg=fixshade_dsp");
    }
}
