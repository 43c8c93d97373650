//! Project tasks: `cargo xtask test` runs every test of the workspace and the no_std
//! builds of the core for the MCU targets.

use std::process::{Command, ExitCode};

mod bake;
mod catalogue;
mod cycles;
mod qemu;
mod raybake;
mod scenes;

/// The MCU targets the core must build for, with the feature sets to try.
const NO_STD_TARGETS: [&str; 2] = ["thumbv6m-none-eabi", "thumbv7em-none-eabihf"];
const FEATURE_SETS: [&str; 5] = ["", "f32-input", "embedded-graphics", "defmt", "fixed"];

fn cargo(args: &[&str]) -> Result<(), String> {
    cargo_env(args, &[])
}

fn cargo_env(args: &[&str], env: &[(&str, &str)]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    eprintln!("xtask: cargo {}", args.join(" "));
    let status = Command::new(&cargo)
        .args(args)
        .envs(env.iter().copied())
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`cargo {}` failed ({status})", args.join(" ")))
    }
}

/// Installs the MCU targets with rustup (a no-op when they are there).
fn ensure_targets() -> Result<(), String> {
    let status = Command::new("rustup")
        .args(["target", "add"])
        .args(NO_STD_TARGETS)
        .status()
        .map_err(|e| format!("cannot run rustup to add the MCU targets: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`rustup target add` failed ({status})"))
    }
}

fn test() -> Result<(), String> {
    // The no_std builds first, so the run closes with the test summary.
    ensure_targets()?;
    for target in NO_STD_TARGETS {
        for features in FEATURE_SETS {
            let mut args = vec!["build", "--release", "-p", "fixshade", "--target", target];
            if !features.is_empty() {
                args.extend(["--features", features]);
            }
            cargo(&args)?;
        }
    }
    // The docs build warning-free (missing docs, broken links).
    cargo_env(
        &["doc", "--no-deps", "--workspace"],
        &[("RUSTDOCFLAGS", "-D warnings")],
    )?;
    // The firmware on QEMU, frames compared with the host (before the tests, so the
    // run closes with the test summary).
    qemu::qemu()?;
    fuzz_build()?;
    cargo(&["test", "--workspace"])
}

/// Builds the fuzz targets (fuzz/, its own workspace) without running them: the dev
/// profile and no sanitizer keep the build short. cargo-fuzz wants a nightly
/// compiler; `RUSTC_BOOTSTRAP=1` lets the stable one take its flags. Installs
/// cargo-fuzz first if it is missing (`--locked`, about a minute).
fn fuzz_build() -> Result<(), String> {
    let have = Command::new("cargo")
        .args(["fuzz", "--version"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !have {
        cargo(&["install", "cargo-fuzz", "--locked"])?;
    }
    eprintln!("xtask: RUSTC_BOOTSTRAP=1 cargo fuzz build --dev --sanitizer none (in fuzz/)");
    let status = Command::new("cargo")
        .args(["fuzz", "build", "--dev", "--sanitizer", "none"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../fuzz"))
        .env("RUSTC_BOOTSTRAP", "1")
        .status()
        .map_err(|e| format!("cannot run cargo fuzz: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`cargo fuzz build` failed ({status})"))
    }
}

const USAGE: &str = "usage: cargo xtask test    (every test, no_std builds for thumbv6m and thumbv7em, docs, qemu, fuzz builds)
       cargo xtask qemu    (firmware on QEMU Cortex-M0 and M4: frames compared with the host, instruction table)
       cargo xtask bake    (writes boards/baked/: the scenes, meshes and catalogues the firmware includes)
       cargo xtask cycles [DIR...] (the module import cycles of each source directory; default crates/sim-host/src)";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("test") => test(),
        Some("qemu") => qemu::qemu(),
        Some("bake") => bake::run(&qemu::root()),
        Some("cycles") => cycles::run(&qemu::root(), &args[1..]),
        Some("help") | Some("--help") | None => {
            eprintln!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Some(other) => Err(format!("unknown task `{other}`\n{USAGE}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}
