//! End-to-end tests of the reference renderer.

use super::*;
use crate::scene::desc::*;

fn camera(projection: Projection) -> CameraDesc {
    CameraDesc {
        eye: [0.0, 0.0, 5.0],
        target: [0.0; 3],
        up: [0.0, 1.0, 0.0],
        projection,
    }
}

fn emissive(c: [f64; 3]) -> MaterialDesc {
    MaterialDesc {
        emission: c,
        ambient: [0.0; 3],
        diffuse: [0.0; 3],
        specular: [0.0; 3],
        shininess: 1.0,
    }
}

fn object(material: MaterialDesc) -> ObjectDesc {
    ObjectDesc {
        mesh: MeshSource::Robot, // placeholder: the meshes are passed explicitly
        translate: [0.0; 3],
        rotate_deg: [0.0; 3],
        scale: 1.0,
        material,
        material_from: Default::default(),
        back_material: None,
    }
}

/// An orthographic 8x8 scene where world (x, y) maps to pixel (x + 4, 4 - y).
fn ortho_scene(objects: Vec<ObjectDesc>) -> SceneDesc {
    SceneDesc {
        width: 8,
        height: 8,
        format: FormatName::RGB888,
        background: [0, 0, 0],
        camera: camera(Projection::Orthographic {
            height: 8.0,
            near: 1.0,
            far: 9.0,
        }),
        lights: vec![],
        global_ambient: [0.0; 3],
        local_viewer: false,
        two_sided: false,
        objects,
        shading: ShadingName::GOURAUD,
        span: SpanName::CLASSIC,
        cull_back: true,
        depth_test: true,
        depth_bits: 16,
        perspective_correct: false,
        perspective_span: crate::scene::desc::DEFAULT_PERSPECTIVE_SPAN,
        specular: crate::scene::desc::SpecularName::EXACT,
        divide: crate::scene::desc::DivideName::EXACT,
        raycast: Default::default(),
        effects: Default::default(),
    }
}

fn flat_mesh(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> MeshData {
    MeshData {
        normals: vec![[0.0, 0.0, 1.0]; positions.len()],
        positions,
        triangles,
    }
}

fn ascii(img: &Image) -> String {
    (0..img.height as usize)
        .map(|y| {
            (0..img.width as usize)
                .map(|x| {
                    if img.covered[y * img.width as usize + x] {
                        '#'
                    } else {
                        '.'
                    }
                })
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Octahedron of radius 1 (a very coarse sphere), counter-clockwise from outside.
fn octahedron() -> MeshData {
    let positions = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    // Check the winding: the face normal points away from the origin.
    for t in &triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let n = matrix::cross(matrix::sub(b, a), matrix::sub(c, a));
        assert!(matrix::dot(n, a) > 0.0);
    }
    MeshData {
        normals: positions.clone(),
        positions,
        triangles,
    }
}

fn lit_scene(width: u32, height: u32) -> SceneDesc {
    SceneDesc {
        width,
        height,
        format: FormatName::RGB565BE,
        background: [10, 20, 30],
        camera: CameraDesc {
            eye: [0.5, 1.0, 4.0],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            projection: Projection::Perspective {
                fovy_deg: 45.0,
                near: 1.0,
                far: 10.0,
            },
        },
        lights: vec![
            LightDesc {
                kind: LightKind::Directional {
                    direction: [1.0, 1.0, 1.0],
                },
                ambient: [0.1; 3],
                diffuse: [0.8, 0.7, 0.6],
                specular: [1.0; 3],
            },
            LightDesc {
                kind: LightKind::Point {
                    position: [-2.0, 0.0, 2.0],
                    attenuation: [1.0, 0.1, 0.05],
                },
                ambient: [0.0; 3],
                diffuse: [0.3, 0.3, 0.9],
                specular: [0.5; 3],
            },
        ],
        global_ambient: [0.2; 3],
        local_viewer: true,
        two_sided: false,
        objects: vec![ObjectDesc {
            mesh: MeshSource::Sphere { lon: 4, lat: 2 },
            translate: [0.0; 3],
            rotate_deg: [10.0, 20.0, 30.0],
            scale: 1.0,
            material: MaterialDesc {
                emission: [0.0; 3],
                ambient: [0.2, 0.2, 0.2],
                diffuse: [0.8, 0.5, 0.3],
                specular: [0.5; 3],
                shininess: 20.0,
            },
            material_from: Default::default(),
            back_material: None,
        }],
        shading: ShadingName::GOURAUD,
        span: SpanName::CLASSIC,
        cull_back: true,
        depth_test: true,
        depth_bits: 16,
        perspective_correct: false,
        perspective_span: crate::scene::desc::DEFAULT_PERSPECTIVE_SPAN,
        specular: crate::scene::desc::SpecularName::EXACT,
        divide: crate::scene::desc::DivideName::EXACT,
        raycast: Default::default(),
        effects: Default::default(),
    }
}

#[test]
fn triangle_covers_known_pixels_through_the_pipeline() {
    // Pixel corners (0,0), (0,8), (8,0): world (-4,4), (-4,-4), (4,4), CCW.
    let mesh = flat_mesh(
        vec![[-4.0, 4.0, 0.0], [-4.0, -4.0, 0.0], [4.0, 4.0, 0.0]],
        vec![[0, 1, 2]],
    );
    let scene = ortho_scene(vec![object(emissive([1.0, 0.5, 0.0]))]);
    let img = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions::default());
    let want = "\
#######.
######..
#####...
####....
###.....
##......
#.......
........";
    assert_eq!(ascii(&img), want);
    for (p, c) in img.pixels.iter().zip(&img.covered) {
        assert_eq!(*p, if *c { [255, 128, 0] } else { [0, 0, 0] });
    }
    // Reversed winding is a back face: culled, or drawn identically without culling.
    let back = flat_mesh(mesh.positions.clone(), vec![[0, 2, 1]]);
    let img = render_reference(&scene, std::slice::from_ref(&back), &RefOptions::default());
    assert_eq!(img.covered_count(), 0);
    let mut no_cull = scene.clone();
    no_cull.cull_back = false;
    let img = render_reference(&no_cull, &[back], &RefOptions::default());
    assert_eq!(ascii(&img), want);
}

#[test]
fn quad_of_two_triangles_covers_every_pixel_once() {
    // A square larger than the view split along its diagonal from world (-5,-5) to
    // (5,5), i.e. screen X + Y = 8, which passes through the pixel centres with
    // x + y = 7. The upper-left triangle is red, the lower-right one green; depth
    // test is off, so whichever is drawn last would win a doubly covered pixel.
    let p = vec![
        [-5.0, 5.0, 0.0],
        [-5.0, -5.0, 0.0],
        [5.0, -5.0, 0.0],
        [5.0, 5.0, 0.0],
    ];
    for (upper, lower) in [([0, 1, 3], [1, 2, 3]), ([3, 0, 1], [2, 3, 1])] {
        let meshes = [
            flat_mesh(p.clone(), vec![upper]),
            flat_mesh(p.clone(), vec![lower]),
        ];
        let objects = [
            object(emissive([1.0, 0.0, 0.0])),
            object(emissive([0.0, 1.0, 0.0])),
        ];
        for order in [[0usize, 1], [1, 0]] {
            let mut scene = ortho_scene(order.iter().map(|&i| objects[i].clone()).collect());
            scene.depth_test = false;
            let m: Vec<MeshData> = order.iter().map(|&i| meshes[i].clone()).collect();
            let img = render_reference(&scene, &m, &RefOptions::default());
            assert_eq!(img.covered_count(), 64);
            for y in 0..8usize {
                for x in 0..8usize {
                    // Centres on the diagonal lie on the right edge of the upper
                    // triangle (excluded) and the left edge of the lower one
                    // (included).
                    let want = if x + y < 7 { [255, 0, 0] } else { [0, 255, 0] };
                    assert_eq!(img.pixels[y * 8 + x], want, "pixel ({x}, {y})");
                }
            }
        }
    }
}

#[test]
fn flat_shading_uses_the_last_vertex() {
    let mesh = flat_mesh(
        vec![[-4.0, 4.0, 0.0], [-4.0, -4.0, 0.0], [4.0, 4.0, 0.0]],
        vec![[0, 1, 2]],
    );
    let mut scene = ortho_scene(vec![object(MaterialDesc {
        emission: [0.0; 3],
        ambient: [1.0; 3],
        diffuse: [0.0; 3],
        specular: [0.0; 3],
        shininess: 1.0,
    })]);
    // A point light whose ambient term depends on the distance: vertex colours
    // differ, so Gouraud varies and flat does not.
    scene.lights = vec![LightDesc {
        kind: LightKind::Point {
            position: [4.0, 4.0, 0.0],
            attenuation: [1.0, 1.0, 0.0],
        },
        ambient: [1.0; 3],
        diffuse: [0.0; 3],
        specular: [0.0; 3],
    }];
    scene.shading = ShadingName::FLAT;
    let img = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions::default());
    // Vertex 2 sits on the light: att = 1.
    for (p, c) in img.pixels.iter().zip(&img.covered) {
        if *c {
            assert_eq!(*p, [255; 3]);
        }
    }
    scene.shading = ShadingName::GOURAUD;
    let img = render_reference(&scene, &[mesh], &RefOptions::default());
    // Gouraud: pixel (0,0) is far from the light, pixel (6,0) next to it.
    assert!(img.pixels[0][0] < img.pixels[6][0]);
}

#[test]
fn depth_test_keeps_the_nearest() {
    let near = flat_mesh(
        vec![[-4.0, 4.0, 1.0], [-4.0, -4.0, 1.0], [4.0, 4.0, 1.0]],
        vec![[0, 1, 2]],
    );
    let far = flat_mesh(
        vec![[-4.0, 4.0, -1.0], [-4.0, -4.0, -1.0], [4.0, 4.0, -1.0]],
        vec![[0, 1, 2]],
    );
    let objs = vec![
        object(emissive([1.0, 0.0, 0.0])),
        object(emissive([0.0, 0.0, 1.0])),
    ];
    let scene = ortho_scene(objs);
    let img = render_reference(&scene, &[near.clone(), far.clone()], &RefOptions::default());
    assert_eq!(img.pixels[0], [255, 0, 0]);
    let mut s = scene.clone();
    s.objects.swap(0, 1);
    let img = render_reference(&s, &[far.clone(), near.clone()], &RefOptions::default());
    assert_eq!(img.pixels[0], [255, 0, 0]);
    // Without depth test the later one wins.
    let mut s = scene.clone();
    s.depth_test = false;
    let img = render_reference(&s, &[near, far], &RefOptions::default());
    assert_eq!(img.pixels[0], [0, 0, 255]);
}

#[test]
fn triangle_crossing_the_near_plane_is_clipped() {
    let mut scene = ortho_scene(vec![object(emissive([0.61, 0.23, 0.97]))]);
    scene.width = 32;
    scene.height = 24;
    scene.camera.projection = Projection::Perspective {
        fovy_deg: 60.0,
        near: 1.0,
        far: 20.0,
    };
    // One vertex behind the camera (eye at z = 5), one beyond the far plane.
    let mesh = flat_mesh(
        vec![[-1.0, -1.0, 0.0], [1.0, -0.5, 8.0], [0.5, 1.0, -30.0]],
        vec![[0, 1, 2]],
    );
    for cull in [false, true] {
        for perspective_correct in [false, true] {
            for phong in [false, true] {
                scene.cull_back = cull;
                scene.perspective_correct = perspective_correct;
                let img =
                    render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions { phong });
                let n = img.covered_count();
                assert!(n > 0 || cull, "nothing drawn");
                for (p, c) in img.pixels.iter().zip(&img.covered) {
                    // Emission only (away from rounding ties): any NaN would have produced 0.
                    assert_eq!(*p, if *c { [156, 59, 247] } else { [0, 0, 0] });
                }
            }
        }
    }
    // Exactly one of the two windings is front-facing.
    scene.cull_back = true;
    let back = flat_mesh(mesh.positions.clone(), vec![[0, 2, 1]]);
    let a = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions::default());
    let b = render_reference(&scene, &[back], &RefOptions::default());
    assert!((a.covered_count() == 0) != (b.covered_count() == 0));
}

#[test]
fn clipping_interpolates_and_stays_finite() {
    let v = |clip: [f64; 4], c: f64| ClipVertex {
        clip,
        colour: [c; 3],
        back: [c; 3],
        normal: [0.0, 0.0, 1.0],
        eye: [0.0, 0.0, -clip[3]],
    };
    // Near plane z = -w: vertex 0 is behind it.
    let tri = [
        v([0.0, 0.0, -3.0, 1.0], 0.0),
        v([1.0, 0.0, 0.0, 1.0], 1.0),
        v([0.0, 1.0, 0.0, 1.0], 1.0),
    ];
    let poly = clip_triangle(tri);
    assert_eq!(poly.len(), 4);
    for p in &poly {
        assert!(near_distance(p) >= -1e-12 && far_distance(p) >= -1e-12);
        assert!(p.clip.iter().chain(&p.colour).all(|x| x.is_finite()));
    }
    // The cut is at t = 1/3 from the inside vertex (colour 1) towards the outside
    // one (colour 0) along each crossing edge.
    let cuts = poly
        .iter()
        .filter(|p| (p.colour[0] - 2.0 / 3.0).abs() < 1e-12);
    assert_eq!(cuts.count(), 2);
    // Shared edges are cut identically in both directions.
    let a = clip_against(&[tri[0], tri[1], tri[2]], near_distance);
    let b = clip_against(&[tri[1], tri[0], tri[2]], near_distance);
    let cut_a: Vec<_> = a
        .iter()
        .filter(|p| p.clip[0] > 0.0 && p.clip[0] < 1.0)
        .collect();
    let cut_b: Vec<_> = b
        .iter()
        .filter(|p| p.clip[0] > 0.0 && p.clip[0] < 1.0)
        .collect();
    assert_eq!(cut_a, cut_b);
    // Entirely outside: nothing.
    let out = [
        v([0.0, 0.0, 5.0, 1.0], 0.0),
        v([1.0, 0.0, 5.0, 1.0], 0.0),
        v([0.0, 1.0, 5.0, 1.0], 0.0),
    ];
    assert!(clip_triangle(out).is_empty());
}

#[test]
fn octahedron_sphere_renders() {
    let mesh = octahedron();
    let mut scene = lit_scene(40, 30);
    for format in [FormatName::RGB565BE, FormatName::RGB888, FormatName::GRAY8] {
        for shading in [ShadingName::FLAT, ShadingName::GOURAUD] {
            for perspective_correct in [false, true] {
                for phong in [false, true] {
                    scene.format = format;
                    scene.shading = shading;
                    scene.perspective_correct = perspective_correct;
                    let img = render_reference(
                        &scene,
                        std::slice::from_ref(&mesh),
                        &RefOptions { phong },
                    );
                    let n = img.covered_count();
                    assert!(n > 100 && n < 40 * 30 / 2, "{n} pixels");
                    // The centre is covered and lit (not black: ambient alone
                    // gives 0.04 + 0.02 per channel).
                    let centre = img.pixels[15 * 40 + 20];
                    assert!(img.covered[15 * 40 + 20]);
                    assert!(centre.iter().all(|&c| c > 0), "{centre:?}");
                    for (p, c) in img.pixels.iter().zip(&img.covered) {
                        if !*c {
                            assert_eq!(*p, [10, 20, 30]);
                        }
                    }
                    if format == FormatName::GRAY8 {
                        assert!(img
                            .pixels
                            .iter()
                            .zip(&img.covered)
                            .all(|(p, c)| !*c || (p[0] == p[1] && p[1] == p[2])));
                    }
                }
            }
        }
    }
    // Without culling and depth test the back faces overwrite some front pixels,
    // but coverage is the same silhouette.
    let culled = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions::default());
    scene.cull_back = false;
    let all = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions::default());
    assert_eq!(culled.covered, all.covered);
    scene.depth_test = false;
    let all = render_reference(&scene, &[mesh], &RefOptions::default());
    assert_eq!(culled.covered, all.covered);
}

#[test]
fn quantise_rounds_per_format() {
    assert_eq!(quantise(FormatName::RGB888, [1.0, 0.5, 0.0]), [255, 128, 0]);
    // 565: 0.5*31 + 0.5 = 16 → expand(16/31) = 132; 0.5*63 + .5 = 32 → 130.
    assert_eq!(
        quantise(FormatName::RGB565LE, [0.5, 0.5, 1.0]),
        [132, 130, 255]
    );
    assert_eq!(quantise(FormatName::GRAY8, [1.0, 1.0, 1.0]), [255; 3]);
    // (77*1 + 0 + 0)/256*255 = 76.70 → 77.
    assert_eq!(quantise(FormatName::GRAY8, [1.0, 0.0, 0.0]), [77; 3]);
}

#[test]
fn perspective_correct_differs_from_affine_on_slanted_triangles() {
    let mut scene = lit_scene(64, 48);
    scene.lights.clear();
    scene.objects[0].rotate_deg = [0.0; 3];
    scene.objects[0].material = MaterialDesc {
        emission: [0.0; 3],
        ambient: [1.0; 3],
        diffuse: [0.0; 3],
        specular: [0.0; 3],
        shininess: 1.0,
    };
    scene.camera.eye = [0.0, 0.0, 3.0];
    scene.format = FormatName::RGB888;
    // A floor-like quad receding in depth; colours vary via the point light's
    // distance-dependent ambient term.
    scene.lights = vec![LightDesc {
        kind: LightKind::Point {
            position: [0.0, -1.0, 2.0],
            attenuation: [0.0, 0.0, 1.0],
        },
        ambient: [1.0; 3],
        diffuse: [0.0; 3],
        specular: [0.0; 3],
    }];
    scene.global_ambient = [0.0; 3];
    let mesh = flat_mesh(
        vec![
            [-2.0, -1.0, 2.0],
            [2.0, -1.0, 2.0],
            [2.0, -1.0, -6.0],
            [-2.0, -1.0, -6.0],
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    scene.cull_back = false;
    let affine = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions::default());
    scene.perspective_correct = true;
    let correct = render_reference(&scene, &[mesh], &RefOptions::default());
    assert_eq!(affine.covered, correct.covered);
    assert!(affine.covered_count() > 100);
    assert_ne!(affine.pixels, correct.pixels);
}

/// Timing of a 320x240 image of about 20k triangles (run with
/// `cargo test --release -p fixshade-sim reference -- --ignored --nocapture`).
#[test]
#[ignore]
fn timing_20k_triangles() {
    // UV sphere, 100 x 100 segments = 19 800 triangles.
    let (lon, lat) = (100u32, 100u32);
    let mut positions = Vec::new();
    for j in 0..=lat {
        let th = std::f64::consts::PI * j as f64 / lat as f64;
        for i in 0..=lon {
            let ph = 2.0 * std::f64::consts::PI * i as f64 / lon as f64;
            positions.push([th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos()]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..lat {
        for i in 0..lon {
            let a = j * (lon + 1) + i;
            let (b, c, d) = (a + 1, a + lon + 1, a + lon + 2);
            if j != 0 {
                triangles.push([a, c, b]);
            }
            if j != lat - 1 {
                triangles.push([b, c, d]);
            }
        }
    }
    let mesh = MeshData {
        normals: positions.clone(),
        positions,
        triangles,
    };
    let mut scene = lit_scene(320, 240);
    scene.camera.eye = [0.0, 0.0, 2.6];
    scene.cull_back = false;
    for phong in [false, true] {
        let t = std::time::Instant::now();
        let img = render_reference(&scene, std::slice::from_ref(&mesh), &RefOptions { phong });
        println!(
            "{} triangles, phong {phong}: {:?}, {} pixels",
            mesh.triangles.len(),
            t.elapsed(),
            img.covered_count()
        );
    }
}
