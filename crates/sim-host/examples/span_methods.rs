//! Renders a scene with every span method and prints each one's NMSE against the
//! exact f64 reference, with seed 002's verdict, the largest error of one 8-bit
//! channel ("max err") and the number of pixels whose coverage differs from the
//! reference's ("cov diff"). "covered" counts the pixels the triangles cover.
//!
//! Run: `cargo run --release -p fixshade-sim --example span_methods [-- SCENE]`
//! (SCENE: a scene file or built-in name, default `teapot`).

use fixshade_sim::image::compare::compare;
use fixshade_sim::render::{reference, render};
use fixshade_sim::scene::desc::{Named, SpanName};
use fixshade_sim::scene::load::load_arg;

fn run() -> Result<(), String> {
    let scene_arg = std::env::args().nth(1).unwrap_or_else(|| "teapot".into());
    let mut ls = load_arg(&scene_arg)?;
    let refimg = reference(&ls, false);
    println!(
        "{scene_arg}: {}x{}, against the f64 Gouraud reference",
        ls.desc.width, ls.desc.height
    );
    println!(
        "{:<17} {:>8} {:>11}  {:<18} {:>9} {:>9}",
        "method", "covered", "NMSE", "verdict", "max err", "cov diff"
    );
    for (span, name) in SpanName::ALL {
        ls.desc.span = *span;
        let r = render(&ls, None)?;
        let c = compare(&refimg, &r.image)?;
        println!(
            "{:<17} {:>8} {:>11.3e}  {:<18} {:>9} {:>9}",
            name,
            r.stats.pixels,
            c.nmse,
            c.verdict.as_str(),
            c.max_channel_error,
            c.coverage_mismatch
        );
    }
    Ok(())
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("span_methods: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
