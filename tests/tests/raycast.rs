//! Pixel-segment ray casting (seed 002 §2.6): the adaptive sampler around the
//! fixed-point ray caster, its agreement with the f64 Phong reference, and
//! degenerate inputs.

use fixshade::fixed::{Angle, Q16_16};
use fixshade::light::{Light, Material};
use fixshade::raycast::{Caster, Plane, RayPixels, RayScene, RayVertex, Sphere, TriBox};
use fixshade::sampler::{fill_blocks, fill_row, PixelFn, Threshold};
use fixshade::scene::{Camera, Projection, Scene};
use fixshade::specular::BlinnExact;
use fixshade::target::{PixelFormat, Rgb888};
use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::render::raycast::{ray_image, Sampling};
use fixshade_sim::scene::convert::threshold_q8;
use fixshade_sim::scene::desc::{FormatName, ShadingName};
use fixshade_sim::scene::load::load_arg;

/// The every-pixel evaluation of `f` over a `w × h` frame.
fn every_pixel<F: PixelFn>(f: &mut F, w: u32, h: u32) -> Vec<[u32; 3]> {
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| f.eval(x, y))
        .collect()
}

/// A costly function given by a closure, counting calls.
struct Counted<G: FnMut(u32, u32) -> [u32; 3]>(G, u32);
impl<G: FnMut(u32, u32) -> [u32; 3]> PixelFn for Counted<G> {
    fn eval(&mut self, x: u32, y: u32) -> [u32; 3] {
        self.1 += 1;
        (self.0)(x, y)
    }
}

fn q(v: i32, d: i32) -> Q16_16 {
    Q16_16::from_ratio(v, d)
}

fn camera(eye_z: i32) -> Camera {
    Camera {
        eye: [Q16_16::ZERO, q(1, 2), Q16_16::from_int(eye_z)],
        target: [Q16_16::ZERO; 3],
        up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
        projection: Projection::Perspective {
            fovy: Angle::from_degrees(45),
            near: q(1, 2),
            far: Q16_16::from_int(40),
        },
    }
}

fn lit_scene<'a>(eye_z: i32) -> Scene<'a> {
    let mut s = Scene::new(camera(eye_z));
    let white = [Q16_16::ONE; 3];
    s.add_light(Light::directional(
        [q(-1, 2), Q16_16::ONE, q(1, 2)],
        white,
        white,
    ))
    .unwrap();
    s
}

fn shiny() -> Material {
    Material {
        specular: [q(1, 2); 3],
        shininess: Q16_16::from_int(30),
        ..Material::default()
    }
}

#[test]
fn segment_one_equals_per_pixel_evaluation_of_the_ray_caster() {
    for name in ["spheres-plane", "robot"] {
        let ls = load_arg(name).unwrap();
        let (w, h) = (ls.desc.width, ls.desc.height);
        let every = ray_image(&ls, Sampling::EVERY_PIXEL).unwrap();
        assert_eq!(every.evaluations, (w * h) as u64, "{name}");
        // The same ray caster evaluated directly at every pixel, without the sampler.
        let d = &ls.desc;
        let scene = fixshade_sim::scene::convert::core_scene(d, &ls.fixed).unwrap();
        let spheres: Vec<Sphere> = d
            .raycast
            .spheres
            .iter()
            .map(|s| Sphere {
                centre: s.centre.map(fixshade_sim::scene::convert::q16),
                radius: fixshade_sim::scene::convert::q16(s.radius),
                material: shiny_from(&s.material),
            })
            .collect();
        let planes: Vec<Plane> = d
            .raycast
            .planes
            .iter()
            .map(|p| Plane {
                point: p.point.map(fixshade_sim::scene::convert::q16),
                normal: p.normal.map(fixshade_sim::scene::convert::q16),
                material: shiny_from(&p.material),
            })
            .collect();
        let rs = RayScene {
            scene: &scene,
            spheres: &spheres,
            planes: &planes,
            shadows: d.raycast.shadows,
        };
        let mut cache = vec![RayVertex::default(); scene.vertex_count()];
        let mut boxes = vec![TriBox::default(); rs.triangle_count()];
        let caster = Caster::<BlinnExact>::prepare(rs, w, h, &mut cache, &mut boxes).unwrap();
        let bg = fixshade_sim::scene::convert::background_channels(d.format, d.background);
        assert_eq!(d.format, FormatName::RGB565LE);
        let mut f = RayPixels::<BlinnExact, fixshade::target::Rgb565Le>::new(&caster, bg);
        let direct = every_pixel(&mut f, w, h);
        assert!(
            direct == every.channels,
            "{name}: L = 1 differs from per-pixel"
        );
        // And the sampled render stays close to it with the default (L, K).
        let def = ray_image(&ls, Sampling::of(&ls.desc)).unwrap();
        let c = compare(&every.image, &def.image).unwrap();
        assert!(def.evaluations < every.evaluations / 2, "{name}");
        println!(
            "{name}: default sampling {} evaluations ({:.3}/px), NMSE {:.2e}",
            def.evaluations,
            def.evaluations as f64 / (w * h) as f64,
            c.nmse
        );
    }
}

fn shiny_from(m: &fixshade_sim::scene::desc::MaterialDesc) -> Material {
    use fixshade_sim::scene::convert::q16;
    Material {
        emission: m.emission.map(q16),
        ambient: m.ambient.map(q16),
        diffuse: m.diffuse.map(q16),
        specular: m.specular.map(q16),
        shininess: q16(m.shininess),
    }
}

#[test]
fn flat_region_costs_one_evaluation_per_segment() {
    // A frame filled by a plane seen head on under a directional light: one colour.
    let mut scene = lit_scene(5);
    scene.camera.eye = [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(5)];
    let planes = [Plane {
        point: [Q16_16::ZERO; 3],
        normal: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE],
        material: Material::default(),
    }];
    let rs = RayScene {
        scene: &scene,
        spheres: &[],
        planes: &planes,
        shadows: true,
    };
    let (w, h) = (97u32, 5u32);
    let caster = Caster::<BlinnExact>::prepare(rs, w, h, &mut [], &mut []).unwrap();
    let mut f = Counted(
        |x, y| RayPixels::<BlinnExact, Rgb888>::new(&caster, [0; 3]).eval(x, y),
        0,
    );
    let all = every_pixel(&mut f, w, h);
    assert!(all.iter().all(|c| *c == all[0] && *c != [0; 3]));
    let k = Threshold::from_q8(0, Rgb888::MAX);
    for l in [2u32, 4, 8, 16] {
        let mut row = vec![[0; 3]; w as usize];
        let n = fill_row(&mut f, 2, l, k, &mut row);
        assert_eq!(n, 1 + (w - 1).div_ceil(l), "L = {l}");
        assert!(row.iter().all(|c| *c == all[0]));
    }
    let mut out = vec![[0; 3]; (w * h) as usize];
    let n = fill_blocks(&mut f, w, h, 8, k, &mut out);
    assert_eq!(n, (1 + (w - 1).div_ceil(8)) * 2);
    assert!(out.iter().all(|c| *c == all[0]));
}

#[test]
fn an_edge_forces_subdivision_to_single_pixels() {
    // A sphere against the background: with K = 0 the sampled frame must equal
    // the every-pixel frame (every edge between differing pixels is resolved down
    // to neighbours) while costing fewer evaluations.
    let scene = lit_scene(6);
    let spheres = [Sphere {
        centre: [Q16_16::ZERO; 3],
        radius: Q16_16::ONE,
        material: Material {
            specular: [Q16_16::ZERO; 3],
            ..Material::default()
        },
    }];
    let rs = RayScene {
        scene: &scene,
        spheres: &spheres,
        planes: &[],
        shadows: false,
    };
    let (w, h) = (64u32, 48u32);
    let caster = Caster::<BlinnExact>::prepare(rs, w, h, &mut [], &mut []).unwrap();
    let mut f = RayPixels::<BlinnExact, Rgb888>::new(&caster, [0, 0, 255]);
    let all = every_pixel(&mut f, w, h);
    let k = Threshold::from_q8(0, Rgb888::MAX);
    let mut evals = 0;
    let mut out = vec![[0; 3]; (w * h) as usize];
    for (y, row) in out.chunks_mut(w as usize).enumerate() {
        evals += fill_row(&mut f, y as u32, 8, k, row);
    }
    // Edge pixels (silhouette: colour next to blue background) are all evaluated,
    // so they match exactly; the sphere's smooth inside may interpolate where its
    // 8-pixel ends are equal, so compare only the rows' edge pixels.
    for y in 0..h as usize {
        for x in 0..w as usize - 1 {
            let (a, b) = (all[y * w as usize + x], all[y * w as usize + x + 1]);
            if (a == [0, 0, 255]) != (b == [0, 0, 255]) {
                assert_eq!(out[y * w as usize + x], a, "({x}, {y})");
                assert_eq!(out[y * w as usize + x + 1], b, "({}, {y})", x + 1);
            }
        }
    }
    assert!(evals < w * h, "{evals}");
    // With a huge K nothing is subdivided: the silhouette is smeared.
    let mut smeared = vec![[0; 3]; (w * h) as usize];
    let big = Threshold::from_q8(256 * 256, Rgb888::MAX);
    let mut e2 = 0;
    for (y, row) in smeared.chunks_mut(w as usize).enumerate() {
        e2 += fill_row(&mut f, y as u32, 8, big, row);
    }
    assert_eq!(e2, h * (1 + (w - 1).div_ceil(8)));
    assert!(smeared != all);
}

#[test]
fn ray_caster_agrees_with_the_phong_reference_on_the_sphere() {
    // The sphere figure in RGB888, every pixel ray cast, against the f64 Phong
    // render of the same tessellated sphere with perspective-correct interpolation
    // (rays interpolate perspective-correctly). Shadows off: the reference has none.
    let mut ls = load_arg("sphere").unwrap();
    ls.desc.format = FormatName::RGB888;
    ls.desc.perspective_correct = true;
    ls.desc.shading = ShadingName::RAYCAST;
    ls.desc.raycast.shadows = false;
    let phong = render::reference(&ls, true);
    let r = ray_image(&ls, Sampling::EVERY_PIXEL).unwrap();
    let c = compare(&phong, &r.image).unwrap();
    println!(
        "sphere ray cast vs Phong: NMSE {:.3e}, max channel error {}, coverage mismatch {}",
        c.nmse, c.max_channel_error, c.coverage_mismatch
    );
    assert!(c.nmse <= 1e-4, "NMSE {}", c.nmse);
    // And against the rasterizer's own Phong render of the same sphere (screen-affine
    // interpolation of normals and positions, fixed point throughout).
    let mut lp = load_arg("sphere").unwrap();
    lp.desc.format = FormatName::RGB888;
    lp.desc.shading = ShadingName::PHONG;
    let raster = render::render(&lp, None).unwrap();
    let cr = compare(&raster.image, &r.image).unwrap();
    println!(
        "sphere ray cast vs rasterized Phong: NMSE {:.3e}, max channel error {}",
        cr.nmse, cr.max_channel_error
    );
    assert!(cr.nmse <= 1e-4, "NMSE {}", cr.nmse);
    // With shadows on, only the terminator (where N·L is small) may darken.
    ls.desc.raycast.shadows = true;
    let rs = ray_image(&ls, Sampling::EVERY_PIXEL).unwrap();
    let cs = compare(&phong, &rs.image).unwrap();
    println!("  with shadows: NMSE {:.3e}", cs.nmse);
    // The pipeline's `shading = "raycast"` is this render with the scene's sampling.
    let p = render::render(&ls, None).unwrap();
    let own = ray_image(&ls, Sampling::of(&ls.desc)).unwrap();
    assert!(p.image.pixels == own.image.pixels);
}

#[test]
fn degenerate_inputs_do_not_panic() {
    let mut scene = lit_scene(4);
    // Ray parallel to a plane: the camera sits in the plane y = 1/2.
    let planes = [
        Plane {
            point: [Q16_16::ZERO, q(1, 2), Q16_16::ZERO],
            normal: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
            material: Material::default(),
        },
        // A zero normal: invisible.
        Plane {
            point: [Q16_16::ZERO; 3],
            normal: [Q16_16::ZERO; 3],
            material: Material::default(),
        },
    ];
    // A sphere grazed by the rays of one row, a zero and a negative radius, and a
    // sphere around the eye.
    let spheres = [
        Sphere {
            centre: [Q16_16::ZERO, q(1, 2) + Q16_16::ONE, Q16_16::ZERO],
            radius: Q16_16::ONE,
            material: shiny(),
        },
        Sphere {
            centre: [Q16_16::ZERO; 3],
            radius: Q16_16::ZERO,
            material: shiny(),
        },
        Sphere {
            centre: [Q16_16::ZERO; 3],
            radius: -Q16_16::ONE,
            material: shiny(),
        },
        Sphere {
            centre: [Q16_16::ZERO, q(1, 2), Q16_16::from_int(4)],
            radius: q(3, 4),
            material: shiny(),
        },
        Sphere {
            centre: [Q16_16::MAX, Q16_16::MIN, Q16_16::MAX],
            radius: Q16_16::MAX,
            material: shiny(),
        },
    ];
    for shadows in [false, true] {
        let rs = RayScene {
            scene: &scene,
            spheres: &spheres,
            planes: &planes,
            shadows,
        };
        for (w, h) in [(1u32, 1u32), (2, 1), (1, 3), (33, 17)] {
            let caster = Caster::<BlinnExact>::prepare(rs, w, h, &mut [], &mut []).unwrap();
            let mut f = RayPixels::<BlinnExact, Rgb888>::new(&caster, [1, 2, 3]);
            let every = every_pixel(&mut f, w, h);
            let mut out = vec![[0; 3]; (w * h) as usize];
            let k = Threshold::from_q8(threshold_q8(8.0), Rgb888::MAX);
            assert!(fill_blocks(&mut f, w, h, 16, k, &mut out) <= w * h);
            for (y, row) in out.chunks_mut(w as usize).enumerate() {
                fill_row(&mut f, y as u32, 16, k, row);
            }
            assert_eq!(every.len(), out.len());
        }
        // Zero-size frames are refused, not drawn.
        assert!(Caster::<BlinnExact>::prepare(rs, 0, 10, &mut [], &mut []).is_err());
        assert!(Caster::<BlinnExact>::prepare(rs, 10, 0, &mut [], &mut []).is_err());
    }
    // No objects and no lights: background everywhere.
    scene.lights.clear();
    let rs = RayScene {
        scene: &scene,
        spheres: &[],
        planes: &[],
        shadows: true,
    };
    let caster = Caster::<BlinnExact>::prepare(rs, 8, 8, &mut [], &mut []).unwrap();
    let mut f = RayPixels::<BlinnExact, Rgb888>::new(&caster, [9, 9, 9]);
    assert!(every_pixel(&mut f, 8, 8).iter().all(|c| *c == [9, 9, 9]));
    // Too many primitives is an error.
    let many = [spheres[0]; 9];
    let rs = RayScene {
        scene: &scene,
        spheres: &many,
        planes: &[],
        shadows: true,
    };
    assert!(Caster::<BlinnExact>::prepare(rs, 8, 8, &mut [], &mut []).is_err());
    // A camera with eye = target is an error.
    scene.camera.target = scene.camera.eye;
    let rs = RayScene {
        scene: &scene,
        spheres: &[],
        planes: &[],
        shadows: true,
    };
    assert!(Caster::<BlinnExact>::prepare(rs, 8, 8, &mut [], &mut []).is_err());
}

#[test]
fn mesh_coverage_equals_the_rasterizer() {
    // Primary rays use the rasterizer's projection and top-left rule: the ray-cast
    // teapot and robot cover exactly the pixels the rasterizer covers.
    for name in ["teapot", "robot"] {
        let mut ls = load_arg(name).unwrap();
        ls.desc.format = FormatName::RGB888;
        let raster = render::render(&ls, None).unwrap();
        ls.desc.shading = ShadingName::RAYCAST;
        ls.desc.raycast.shadows = false;
        let r = ray_image(&ls, Sampling::EVERY_PIXEL).unwrap();
        let c = compare(&raster.image, &r.image).unwrap();
        assert_eq!(c.coverage_mismatch, 0, "{name}");
    }
}
