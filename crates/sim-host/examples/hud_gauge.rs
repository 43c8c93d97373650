//! A HUD gauge over embedded-graphics text: fixshade models drawn as
//! embedded-graphics `Drawable`s into an `embedded-graphics-simulator` display
//! (no SDL window: the display is saved as a PNG).
//!
//! * The gauge: an orthographic, flat-shaded bezel of 27 facets and a needle, with
//!   a Gouraud-shaded hub (a small sphere) drawn over its centre.
//! * A Gouraud-shaded teapot beside it.
//! * Text and a frame drawn by embedded-graphics around them.
//!
//! Each model renders in bands of 8 rows into a small scratch strip and reaches the
//! display as one `fill_contiguous` call per run of covered pixels, so the text and
//! shapes around it are left alone.
//!
//! Run: `cargo run --release -p fixshade-sim --example hud_gauge [-- OUT.png]`
//! (default `out/hud_gauge.png`). `crates/sim-host/tests/examples.rs` runs it and
//! checks the picture.

use std::path::{Path, PathBuf};

use embedded_graphics::mono_font::ascii::{FONT_10X20, FONT_6X10};
use embedded_graphics::mono_font::MonoTextStyle;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{PrimitiveStyle, Rectangle, RoundedRectangle};
use embedded_graphics::text::Text;
use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay};
use fixshade::present::eg::{CoveredPixel, Model};
// Both preludes export an `Angle`: name fixshade's explicitly.
use fixshade::fixed::Angle;
use fixshade::prelude::*;
use fixshade_sim::scene::convert::FixedMesh;
use fixshade_sim::scene::desc::MeshData;
use fixshade_sim::scene::mesh::{sphere, teapot};

/// Display size.
pub const SIZE: Size = Size::new(320, 240);
/// The text colour: pure green, which no model in the picture produces.
pub const TEXT: Rgb565 = Rgb565::GREEN;
/// Display background.
pub const BACKGROUND: Rgb565 = Rgb565::new(2, 5, 5);
/// Where the gauge model (flat bezel and needle, Gouraud hub) sits.
pub const GAUGE: Rectangle = Rectangle::new(Point::new(14, 40), Size::new(150, 150));
/// Where the teapot model sits.
pub const TEAPOT: Rectangle = Rectangle::new(Point::new(172, 60), Size::new(136, 110));

/// The gauge's value, 0..=1 of its sweep.
const VALUE: f64 = 0.62;

/// The bezel: 27 facets on a ring of radii 0.78..1, 270° from lower left over the
/// top to lower right, each facet tilted 40° outwards (its own four vertices with
/// the facet normal, so flat shading gives each facet one shade); and the needle, a
/// thin triangle at `VALUE` of the sweep, facing the viewer.
pub fn gauge_meshes() -> (MeshData, MeshData) {
    let mut ring = MeshData {
        positions: Vec::new(),
        normals: Vec::new(),
        triangles: Vec::new(),
    };
    let n = 27;
    let (a0, sweep) = (225f64.to_radians(), -270f64.to_radians());
    let tilt = 40f64.to_radians();
    for i in 0..n {
        let (t0, t1) = (i as f64 / n as f64, (i as f64 + 0.92) / n as f64);
        let (a, b) = (a0 + sweep * t0, a0 + sweep * t1);
        let m = (a + b) / 2.0;
        let nrm = [m.cos() * tilt.sin(), m.sin() * tilt.sin(), tilt.cos()];
        let base = ring.positions.len() as u32;
        for (r, ang) in [(0.78, a), (1.0, a), (1.0, b), (0.78, b)] {
            ring.positions.push([r * ang.cos(), r * ang.sin(), 0.0]);
            ring.normals.push(nrm);
        }
        // The sweep runs clockwise: (inner a, inner b, outer b) is counter-clockwise.
        ring.triangles.push([base, base + 3, base + 2]);
        ring.triangles.push([base, base + 2, base + 1]);
    }
    let v = a0 + sweep * VALUE;
    let (c, s) = (v.cos(), v.sin());
    let (px, py) = (-s, c); // perpendicular
    let needle = MeshData {
        positions: vec![
            [0.07 * px, 0.07 * py, 0.01],
            [-0.07 * px, -0.07 * py, 0.01],
            [0.74 * c, 0.74 * s, 0.01],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 3],
        triangles: vec![[0, 1, 2]],
    };
    let needle = if orient(&needle) > 0.0 {
        needle
    } else {
        MeshData {
            triangles: vec![[1, 0, 2]],
            ..needle
        }
    };
    (ring, needle)
}

/// Twice the signed area of a one-triangle mesh's triangle in the xy plane.
fn orient(m: &MeshData) -> f64 {
    let [a, b, c] = m.triangles[0].map(|i| m.positions[i as usize]);
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The orthographic camera of the gauge (2.3 units tall, looking down -z).
fn gauge_camera() -> Camera {
    Camera::orthographic(
        [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(5)],
        [Q16_16::ZERO; 3],
        Q16_16::from_ratio(23, 10),
    )
}

/// Light from the upper left, in front.
fn key_light() -> Light {
    let q = |n| Q16_16::from_ratio(n, 10);
    Light::directional([q(-6), q(7), q(8)], rgb(255, 250, 240), rgb(255, 255, 255))
}

/// The flat-shaded part of the gauge: bezel and needle.
pub fn gauge_scene<'a>(ring: &'a FixedMesh, needle: &'a FixedMesh) -> Result<Scene<'a>, String> {
    let e = |e: CapacityError| e.to_string();
    let m = |f: &'a FixedMesh| f.mesh().map_err(|e| e.to_string());
    Scene::new(gauge_camera())
        .with_shading(ShadingMode::Flat)
        .with_light(key_light())
        .map_err(e)?
        .with_object(
            Object::new(m(ring)?)
                .with_material(Material::default().with_diffuse(rgb(110, 140, 175))),
        )
        .map_err(e)?
        .with_object(
            Object::new(m(needle)?)
                .with_material(Material::default().with_diffuse(rgb(235, 60, 35))),
        )
        .map_err(e)
}

/// The Gouraud-shaded hub over the gauge's centre (same camera and frame).
pub fn hub_scene(ball: &FixedMesh) -> Result<Scene<'_>, String> {
    let obj = Object::new(ball.mesh().map_err(|e| e.to_string())?)
        .scaled(Q16_16::from_ratio(14, 100))
        .translated([Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_ratio(1, 10)])
        .with_material(
            Material::default()
                .with_diffuse(rgb(200, 200, 210))
                .with_specular(rgb(255, 255, 255), 30),
        );
    Scene::new(gauge_camera())
        .with_light(key_light())
        .and_then(|s| s.with_object(obj))
        .map_err(|e| e.to_string())
}

/// The Gouraud-shaded teapot (orthographic too, turned to show spout and handle).
pub fn teapot_scene(pot: &FixedMesh) -> Result<Scene<'_>, String> {
    let obj = Object::new(pot.mesh().map_err(|e| e.to_string())?)
        .rotated([
            Angle::from_degrees(20),
            Angle::from_degrees(-30),
            Angle::from_degrees(0),
        ])
        .with_material(
            Material::default()
                .with_diffuse(rgb(235, 130, 40))
                .with_specular(rgb(255, 255, 255), 40),
        );
    Scene::new(Camera::orthographic(
        [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(5)],
        [Q16_16::ZERO; 3],
        Q16_16::from_ratio(17, 10),
    ))
    .with_light(key_light())
    .and_then(|s| s.with_object(obj))
    .map_err(|e| e.to_string())
}

/// The meshes of the picture, in the core's formats: ring, needle, hub, teapot.
pub fn meshes() -> Result<[FixedMesh; 4], String> {
    let (ring, needle) = gauge_meshes();
    Ok([
        FixedMesh::from_mesh(&ring)?,
        FixedMesh::from_mesh(&needle)?,
        FixedMesh::from_mesh(&sphere(24, 16))?,
        FixedMesh::from_mesh(&teapot(6))?,
    ])
}

/// Draws `scene` as a model occupying `area` of `display`.
fn draw_model(
    display: &mut SimulatorDisplay<Rgb565>,
    scene: &Scene<'_>,
    area: Rectangle,
) -> Result<Stats, String> {
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    // Scratch for 8 rows: the model never needs a framebuffer of its own.
    let rows = 8 * area.size.width as usize;
    let mut color = vec![CoveredPixel::default(); rows];
    let mut depth = vec![0u16; rows];
    let model =
        Model::<Rgb565Le>::prepare(scene, area.size, &mut cache, &mut color, Some(&mut depth))
            .map_err(|e| e.to_string())?
            .at(area.top_left);
    match model.draw(display) {
        Ok(r) => r.map_err(|e| e.to_string()),
        Err(e) => match e {},
    }
}

/// Draws the whole picture; also returns the bounding boxes of the text.
pub fn draw() -> Result<(SimulatorDisplay<Rgb565>, Vec<Rectangle>), String> {
    let mut display = SimulatorDisplay::<Rgb565>::with_default_color(SIZE, BACKGROUND);
    let [ring, needle, ball, pot] = meshes()?;

    draw_model(&mut display, &gauge_scene(&ring, &needle)?, GAUGE)?;
    draw_model(&mut display, &hub_scene(&ball)?, GAUGE)?;
    draw_model(&mut display, &teapot_scene(&pot)?, TEAPOT)?;

    let big = MonoTextStyle::new(&FONT_10X20, TEXT);
    let small = MonoTextStyle::new(&FONT_6X10, TEXT);
    let mut boxes = Vec::new();
    let ok = |r: Result<Point, core::convert::Infallible>| match r {
        Ok(p) => p,
        Err(e) => match e {},
    };
    for (text, at, style) in [
        ("fixshade + embedded-graphics", Point::new(12, 24), big),
        ("62 %", Point::new(70, 176), big),
        ("THROTTLE", Point::new(65, 200), small),
        ("orthographic, flat + Gouraud", Point::new(12, 228), small),
        ("teapot, Gouraud", Point::new(195, 190), small),
    ] {
        let t = Text::new(text, at, style);
        boxes.push(t.bounding_box());
        ok(t.draw(&mut display));
    }
    let frame = RoundedRectangle::with_equal_corners(
        Rectangle::new(Point::new(4, 4), SIZE - Size::new(8, 8)),
        Size::new(10, 10),
    );
    match frame
        .into_styled(PrimitiveStyle::with_stroke(Rgb565::new(8, 30, 24), 2))
        .draw(&mut display)
    {
        Ok(()) => {}
        Err(e) => match e {},
    }
    Ok((display, boxes))
}

/// Draws the picture and saves it as a PNG at `out`.
pub fn run(out: &Path) -> Result<(), String> {
    let (display, _) = draw()?;
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    display
        .to_rgb_output_image(&OutputSettings::default())
        .save_png(out)
        .map_err(|e| format!("{}: {e}", out.display()))
}

#[allow(dead_code)] // the test includes this file for `run` and the scenes
fn main() -> std::process::ExitCode {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/hud_gauge.png".into()),
    );
    match run(&out) {
        Ok(()) => {
            println!("{}", out.display());
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("hud_gauge: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
