//! Phong shading (`--shading phong`) and the specular models in the pipeline:
//! accuracy against the exact f64 Phong reference, the even/odd fill bit-identical
//! to the row fill, strips identical to the full frame, and the hard cases of the
//! specular issue (n = 1 and 1000, N·H at 1, opposite normals, light behind).

use fixshade::fixed::{Q16_16, Q2_14};
use fixshade::geometry::Mesh;
use fixshade::light::{Light, Material};
use fixshade::raster::span::{Gradient, NoDepth};
use fixshade::render::{Frame, XfVertex};
use fixshade::scene::{Camera, Object, Placement, Projection, Scene, ShadingMode};
use fixshade::shade::Phong;
use fixshade::target::{Framebuffer, Rgb888};
use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::scene::desc::{LightKind, Named, ShadingName, SpecularName};
use fixshade_sim::scene::load;

const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

#[test]
fn phong_with_exact_specular_matches_the_reference() {
    println!("figure    model             NMSE vs exact f64 Phong");
    for fig in FIGURES {
        let mut ls = load::load_arg(fig).unwrap();
        ls.desc.shading = ShadingName::PHONG;
        let reference = render::matching_reference(&ls);
        let exact = compare(&reference, &render::render(&ls, None).unwrap().image).unwrap();
        println!("{fig:8}  {:16}  {:.3e}", "exact", exact.nmse);
        assert_eq!(exact.coverage_mismatch, 0, "{fig}");
        assert!(exact.nmse <= 1e-5, "{fig}: NMSE {}", exact.nmse);
        // Every approximate model is reported; each must actually change the image
        // (a model that were not wired in would reproduce the exact one).
        for &(model, name) in &SpecularName::ALL[1..] {
            ls.desc.specular = model;
            let c = compare(&reference, &render::render(&ls, None).unwrap().image).unwrap();
            println!("{fig:8}  {name:16}  {:.3e}", c.nmse);
            assert_eq!(c.coverage_mismatch, 0, "{fig} {name}");
            assert!(c.nmse > exact.nmse, "{fig} {name}: {} ≤ exact", c.nmse);
        }
        ls.desc.specular = SpecularName::EXACT;
    }
}

#[test]
fn even_odd_fill_and_strips_are_bit_identical() {
    for fig in FIGURES {
        let mut ls = load::load_arg(fig).unwrap();
        ls.desc.shading = ShadingName::PHONG;
        let rows = render::render(&ls, None).unwrap();
        ls.desc.shading = ShadingName::PHONG_EVEN_ODD;
        let eo = render::render(&ls, None).unwrap();
        assert_eq!(rows.bytes, eo.bytes, "{fig}: even/odd differs from rows");
        assert_eq!(rows.stats, eo.stats, "{fig}");
        for strip in [1, 7, 16] {
            let s = render::render(&ls, Some(strip)).unwrap();
            assert_eq!(rows.bytes, s.bytes, "{fig}: strips of {strip} rows differ");
        }
    }
}

#[test]
fn extreme_exponents_stay_exact() {
    for n in [1.0, 1000.0] {
        for fig in ["sphere", "teapot"] {
            let mut ls = load::load_arg(fig).unwrap();
            ls.desc.shading = ShadingName::PHONG;
            for o in &mut ls.desc.objects {
                o.material.shininess = n;
            }
            let reference = render::matching_reference(&ls);
            let c = compare(&reference, &render::render(&ls, None).unwrap().image).unwrap();
            println!(
                "{fig} n = {n}: NMSE {:.3e}, max error {}",
                c.nmse, c.max_channel_error
            );
            assert!(c.nmse <= 1e-5, "{fig} n = {n}: NMSE {}", c.nmse);
        }
    }
}

#[test]
fn light_behind_the_surface_leaves_ambient_only() {
    let mut ls = load::load_arg("sphere").unwrap();
    ls.desc.shading = ShadingName::PHONG;
    for l in &mut ls.desc.lights {
        l.kind = LightKind::Directional {
            direction: [0.0, 0.0, -1.0],
        };
    }
    let reference = render::matching_reference(&ls);
    let r = render::render(&ls, None).unwrap();
    let c = compare(&reference, &r.image).unwrap();
    assert!(c.nmse <= 1e-5, "NMSE {}", c.nmse);
    // Ambient only: every covered pixel has one colour.
    let lit: Vec<_> = r
        .image
        .pixels
        .iter()
        .zip(&r.image.covered)
        .filter(|(_, c)| **c)
        .map(|(p, _)| *p)
        .collect();
    assert!(lit.len() > 1000);
    assert!(lit.iter().all(|p| *p == lit[0]), "{:?}", &lit[..4]);
}

/// A quad facing the camera lit by a light along the view axis: N·H is exactly 1
/// at every pixel (up to the normal's own rounding), so every pixel gets the full
/// highlight; with opposite vertex normals the interpolated normal passes through
/// zero length and the renderer must neither panic nor write outside.
fn quad_scene_render(normals: [[Q2_14; 3]; 4], n: i32) -> (Vec<[u8; 3]>, u32) {
    static POS: [[Q16_16; 3]; 4] = {
        let (m, p, z) = (Q16_16::from_int(-1), Q16_16::ONE, Q16_16::ZERO);
        [[m, m, z], [p, m, z], [p, p, z], [m, p, z]]
    };
    static TRI: [[u16; 3]; 2] = [[0, 1, 2], [0, 2, 3]];
    let camera = Camera {
        eye: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)],
        target: [Q16_16::ZERO; 3],
        up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
        projection: Projection::Perspective {
            fovy: fixshade::fixed::Angle::from_degrees(60),
            near: Q16_16::ONE,
            far: Q16_16::from_int(10),
        },
    };
    let mut scene = Scene::new(camera);
    scene.shading = ShadingMode::Phong;
    scene.depth_test = false;
    scene.cull_back = false;
    let white = [Q16_16::ONE; 3];
    scene
        .add_light(Light::directional(
            [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE],
            [Q16_16::ZERO; 3],
            white,
        ))
        .unwrap();
    scene.global_ambient = [Q16_16::ZERO; 3];
    let material = Material {
        ambient: [Q16_16::ZERO; 3],
        diffuse: [Q16_16::ZERO; 3],
        specular: white,
        shininess: Q16_16::from_int(n),
        ..Material::default()
    };
    let mesh = Mesh::new(&POS, &normals, &TRI).unwrap();
    scene
        .add_object(Object {
            mesh,
            placement: Placement::default(),
            material,
            back_material: None,
        })
        .unwrap();
    let (w, h) = (40, 30);
    let mut color = vec![[0u8; 3]; 40 * 30];
    let mut cache = [XfVertex::default(); 4];
    let frame = Frame::<Rgb888>::prepare(&scene, w, h, &mut cache).unwrap();
    let mut fb = Framebuffer::<Rgb888>::new(&mut color, None, w, h).unwrap();
    let st = frame
        .draw_with::<Gradient, NoDepth, Phong, _>(&mut fb)
        .unwrap();
    (color, st.pixels)
}

#[test]
fn highlight_at_n_dot_h_one_is_full() {
    let up = [Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE];
    for n in [1, 1000] {
        let (px, covered) = quad_scene_render([up; 4], n);
        assert!(covered > 200);
        let lit = px.iter().filter(|p| **p != [0, 0, 0]).count();
        assert_eq!(lit as u32, covered, "n = {n}");
        assert!(
            px.iter()
                .filter(|p| **p != [0, 0, 0])
                .all(|p| *p == [255; 3]),
            "n = {n}"
        );
    }
}

#[test]
fn opposite_vertex_normals_do_not_break_anything() {
    let up = [Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE];
    let down = [
        Q2_14::from_bits(0),
        Q2_14::from_bits(0),
        Q2_14::from_bits(-(1 << 14)),
    ];
    // Corners 0 and 2 face the light, 1 and 3 face away: along the diagonals the
    // interpolated normal shrinks to zero length.
    let (px, covered) = quad_scene_render([up, down, up, down], 1000);
    assert!(covered > 200);
    // Where the normal faces away the highlight is gone; where it faces the light
    // it is full; nothing else is written outside the covered area.
    assert!(px.contains(&[255; 3]));
    assert!(px.contains(&[0; 3]));
}

#[test]
fn vertices_anywhere_in_i32_are_culled_not_wrapped() {
    use fixshade::raster::phong::{draw_phong, PhongVertex, PixelLight, Rows};
    struct White;
    impl PixelLight for White {
        fn light(&self, _: [i32; 3], _: [i32; 3]) -> [i32; 3] {
            [1 << 16; 3]
        }
    }
    let mut px = [[0u8; 3]; 16];
    let mut fb = Framebuffer::<Rgb888>::new(&mut px, None, 4, 4).unwrap();
    for bad in [i32::MIN, i32::MAX, -(4096 << 4), 4096 << 4] {
        let v = |x: i32, y: i32| PhongVertex {
            x,
            y,
            z: 0,
            n: [0, 0, 1 << 30],
            p: [0; 3],
        };
        let t = [v(bad, 0), v(64, 0), v(0, 64)];
        assert_eq!(
            draw_phong::<Rgb888, _, NoDepth, Rows, _>(&mut fb, t, &White),
            0
        );
        let t = [v(0, 0), v(64, bad), v(0, 64)];
        assert_eq!(
            draw_phong::<Rgb888, _, NoDepth, Rows, _>(&mut fb, t, &White),
            0
        );
    }
    assert!(px.iter().all(|p| *p == [0; 3]));
}
