//! Renders a scene file (or a built-in scene) with the library's front door,
//! `Renderer::new(&mut framebuffer).draw(&scene, &mut cache)`, and writes a PNG.
//!
//! Run: `cargo run --release -p fixshade-sim --example render_scene -- SCENE [OUT.png]`
//! (SCENE: a TOML scene file such as `crates/sim-host/scenes/robot.toml`, or a
//! built-in name: sphere, teapot, robot, bench-sphere; OUT defaults to
//! `out/render_scene.png`). The scene's span method and shading are honoured; the
//! frame is rendered as Rgb888 whatever the scene's format.

use std::path::PathBuf;

use fixshade::prelude::*;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::load::load_arg;
use fixshade_sim::with_span_method;

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let Some(scene_arg) = args.next() else {
        return Err("usage: render_scene SCENE [OUT.png]".into());
    };
    let out = PathBuf::from(args.next().unwrap_or_else(|| "out/render_scene.png".into()));

    // The host side: parse the scene file, build and quantise the meshes.
    let ls = load_arg(&scene_arg)?;
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed)?;

    // The library side: caller-owned buffers, one call to render.
    let (w, h) = (d.width, d.height);
    let n = (w * h) as usize;
    let mut color = vec![d.background; n];
    let mut depth = vec![0xFFFFu16; n];
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let mut fb = Framebuffer::<Rgb888>::new(&mut color, Some(&mut depth), w, h)
        .map_err(|e| e.to_string())?;
    let stats =
        with_span_method!(d.span, S => Renderer::new(&mut fb).span::<S>().draw(&scene, &mut cache))
            .map_err(|e| format!("{scene_arg}: {e}"))?;

    fixshade_sim::chart::png::write_rgb(&out, w, h, &[color.as_flattened()], 1, &[])?;
    println!(
        "{}: {} triangles, {} drawn, {} pixels -> {}",
        scene_arg,
        stats.triangles,
        stats.drawn,
        stats.pixels,
        out.display()
    );
    Ok(())
}

fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("render_scene: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
