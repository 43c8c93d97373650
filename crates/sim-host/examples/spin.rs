//! A spinning teapot as an animated PNG: the library's `Renderer` draws each frame
//! into a 200x160 Rgb565 framebuffer (the model turns 10° about y per frame), and
//! the frames are written as one APNG (any browser plays it) by the simulator's PNG
//! writer (`fixshade_sim::chart::png`).
//!
//! Run: `cargo run --release -p fixshade-sim --example spin [-- OUT.png [FRAMES]]`
//! (default `out/spin.png`, 36 frames: one full turn).

use std::path::PathBuf;
use std::process::ExitCode;

use fixshade::prelude::*;
use fixshade_sim::scene::convert::FixedMesh;
use fixshade_sim::scene::mesh::teapot;

const W: u32 = 200;
const H: u32 = 160;

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "out/spin.png".into()));
    let frames: u32 = match args.next() {
        Some(s) => s
            .parse()
            .ok()
            .filter(|n| (1..=360).contains(n))
            .ok_or_else(|| format!("FRAMES must be 1..=360, got `{s}`"))?,
        None => 36,
    };

    // The teapot, built on the host and converted to the core's fixed-point mesh.
    let fixed = FixedMesh::from_mesh(&teapot(6))?;
    let mesh = fixed.mesh().map_err(|e| e.to_string())?;

    let q = |v: i32, den: i32| Q16_16::from_ratio(v, den);
    let eye = [Q16_16::ZERO, q(1, 2), q(5, 2)];
    let camera = Camera::perspective(eye, [Q16_16::ZERO; 3], Angle::from_degrees(45))
        .with_depth_range(Q16_16::ONE, Q16_16::from_int(5));
    let porcelain = Material::default()
        .with_diffuse(rgb(90, 160, 230))
        .with_specular(rgb(255, 255, 255), 40);
    let key = Light::directional(
        [q(-6, 10), q(7, 10), q(8, 10)],
        rgb(255, 248, 235),
        rgb(255, 255, 255),
    );

    let n = (W * H) as usize;
    let mut color = vec![0u16; n];
    let mut depth = vec![0xFFFFu16; n];
    let mut cache = vec![XfVertex::default(); mesh.positions().len()];
    let mut rgb8 = Vec::with_capacity(frames as usize);
    for i in 0..frames {
        let turn = Angle::from_turns_bits(((i as u64) << 32).div_euclid(frames as u64) as u32);
        let scene = Scene::new(camera)
            .with_light(key)
            .map_err(|e| e.to_string())?
            .with_object(
                Object::new(mesh)
                    .rotated([Angle::from_degrees(0), turn, Angle::from_degrees(0)])
                    .with_material(porcelain),
            )
            .map_err(|e| e.to_string())?;
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), W, H)
            .map_err(|e| e.to_string())?;
        fb.clear(Rgb565Le::pack(2, 5, 4));
        Renderer::new(&mut fb)
            .draw(&scene, &mut cache)
            .map_err(|e| e.to_string())?;
        // 5-6-5 channels expanded to 8 bits for the PNG.
        let frame: Vec<u8> = color
            .iter()
            .flat_map(|p| {
                let [r, g, b] = Rgb565Le::unpack(*p);
                [
                    (r * 255 + 15) / 31,
                    (g * 255 + 31) / 63,
                    (b * 255 + 15) / 31,
                ]
                .map(|v| v as u8)
            })
            .collect();
        rgb8.push(frame);
    }

    let frames_rgb: Vec<&[u8]> = rgb8.iter().map(Vec::as_slice).collect();
    fixshade_sim::chart::png::write_rgb(&out, W, H, &frames_rgb, 15, &[])?;
    println!(
        "{frames} frames of {W}x{H} -> {} (animated PNG, 15 frames/s)",
        out.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("spin: {e}");
            ExitCode::FAILURE
        }
    }
}
