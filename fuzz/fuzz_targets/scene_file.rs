//! The scene-file parser on arbitrary text; a scene that parses is then converted
//! to the core's scene (over a small fixed mesh per object) and its vertex stage,
//! clipper and rasterizer run into one-row strips at the top, middle and bottom of
//! its frame, with two-sided lighting when the scene asks for it
//! (`two_sided = true`) and the depth cells its `depth_bits` asks for. Asserted: no
//! panic; errors name the file and a line inside it.
#![no_main]

use fixshade::effects::TwoSided;
use fixshade::specular::Specular;
use fixshade::render::{Frame, XfVertex};
use fixshade::scene::Scene;
use fixshade::target::{Rgb888, Strip};
use fixshade_sim::scene::convert::{core_scene, quantize_scene, FixedMesh};
use fixshade_sim::scene::desc::MeshData;
use fixshade_sim::scene::file::parse_scene;
use fixshade_sim::with_span_method;
use libfuzzer_sys::fuzz_target;

/// A tetrahedron.
fn mesh() -> FixedMesh {
    let p = [
        [1.0, 1.0, 1.0],
        [1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
    ];
    let s = 1.0 / 3f64.sqrt();
    let m = MeshData {
        positions: p.to_vec(),
        normals: p.iter().map(|v| v.map(|c| c * s)).collect(),
        triangles: vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    };
    FixedMesh::from_mesh(&m).expect("tetrahedron")
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let d = match parse_scene(text, "fuzz.toml") {
        Err(e) => {
            assert_eq!(e.file, "fuzz.toml");
            if let Some(line) = e.line {
                assert!(line >= 1 && line <= text.lines().count().max(1) + 1, "{e}");
            }
            return;
        }
        Ok(d) => d,
    };
    let d = quantize_scene(&d);
    let meshes: Vec<FixedMesh> = d.objects.iter().map(|_| mesh()).collect();
    let Ok(scene) = core_scene(&d, &meshes) else {
        return;
    };
    if d.two_sided {
        draw::<TwoSided>(&scene, &d);
    } else {
        draw::<fixshade::specular::BlinnExact>(&scene, &d);
    }
});

/// Prepares and draws `scene` lit with `Sp` into three one-row strips.
fn draw<Sp: Specular>(scene: &Scene<'_>, d: &fixshade_sim::scene::desc::SceneDesc) {
    let mut cache = vec![XfVertex::default(); Frame::<Rgb888, Sp>::cache_len(scene)];
    let Ok(frame) = Frame::<Rgb888>::prepare_with::<Sp>(scene, d.width, d.height, &mut cache)
    else {
        return;
    };
    let w = d.width as usize;
    let mut color = vec![[0u8; 3]; w];
    let mut depth = vec![0xFFFFu16; w];
    let mut depth32 = vec![u32::MAX; w];
    for y0 in [0, d.height / 2, d.height - 1] {
        // The depth cells the scene asks for (`depth_bits`).
        if d.depth_bits == 32 {
            let mut strip = Strip::<Rgb888, u32>::with_depth_format(
                &mut color,
                Some(&mut depth32),
                d.width,
                d.height,
                y0,
                1,
            )
            .expect("one-row strip");
            let _ = with_span_method!(d.span, S => frame.draw::<S, _>(&mut strip));
        } else {
            let mut strip =
                Strip::<Rgb888>::new(&mut color, Some(&mut depth), d.width, d.height, y0, 1)
                    .expect("one-row strip");
            let _ = with_span_method!(d.span, S => frame.draw::<S, _>(&mut strip));
        }
    }
}
