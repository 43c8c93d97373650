//! The quadratic intensity surface (`--shading quadratic`, seed 003): accuracy
//! against the exact Phong reference, coverage identical to `gradient`, the 2×2
//! block fill bit-identical to the row fill, and planar samples reproducing Gouraud.

use fixshade::raster::quadratic::{draw_quadratic, Fill};
use fixshade::raster::span::{DepthTest, Gradient};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::render::{Frame, Stats, XfVertex};
use fixshade::shade::{Gouraud, QuadraticSurface, QuadraticSurfaceRows, Shading};
use fixshade::target::{Framebuffer, Rgb888, Strip};
use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::desc::{FormatName, ShadingName, SpanName};
use fixshade_sim::scene::load;
use fixshade_sim::scene::load::LoadedScene;

const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

#[test]
fn quadratic_beats_gouraud_against_phong() {
    println!("figure    Gouraud NMSE   quadratic NMSE   (both vs exact Phong)");
    for fig in FIGURES {
        let mut ls = load::load_arg(fig).unwrap();
        let phong = render::reference(&ls, true);
        ls.desc.shading = ShadingName::GOURAUD;
        let g = compare(&phong, &render::render(&ls, None).unwrap().image).unwrap();
        ls.desc.shading = ShadingName::QUADRATIC;
        let r = render::render(&ls, None).unwrap();
        let q = compare(&phong, &r.image).unwrap();
        println!("{fig:8}  {:12.3e}   {:14.3e}", g.nmse, q.nmse);
        assert_eq!(q.coverage_mismatch, 0, "{fig}");
        assert_eq!(
            r.stats.fallback, 0,
            "{fig}: nothing is clipped in the figures"
        );
        if fig != "robot" {
            assert!(
                q.nmse < g.nmse,
                "{fig}: quadratic NMSE {} is not below Gouraud's {}",
                q.nmse,
                g.nmse
            );
        }
    }
}

/// Draws `ls` with the shading `Sh` and the depth test into a fresh framebuffer;
/// returns colour, depth and stats.
fn draw_frame<Sh: Shading>(ls: &LoadedScene) -> (Vec<[u8; 3]>, Vec<u16>, Stats) {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed).unwrap();
    let (w, h) = (d.width, d.height);
    let n = (w * h) as usize;
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<Rgb888>::prepare(&scene, w, h, &mut cache).unwrap();
    let mut color = vec![[0u8; 3]; n];
    let mut depth = vec![0xFFFFu16; n];
    let mut fb = Framebuffer::<Rgb888>::new(&mut color, Some(&mut depth), w, h).unwrap();
    let st = frame
        .draw_with::<Gradient, DepthTest, Sh, _>(&mut fb)
        .unwrap();
    (color, depth, st)
}

#[test]
fn figures_blocks_equal_rows_and_cover_like_gradient() {
    for fig in FIGURES {
        let mut ls = load::load_arg(fig).unwrap();
        ls.desc.format = FormatName::RGB888;
        let (cb, db, sb) = draw_frame::<QuadraticSurface>(&ls);
        let (cr, dr, sr) = draw_frame::<QuadraticSurfaceRows>(&ls);
        let (_, dg, sg) = draw_frame::<Gouraud>(&ls);
        assert!(cb == cr, "{fig}: 2×2 blocks differ from rows");
        assert_eq!(db, dr, "{fig}");
        // Same covered pixels with the same depths: same coverage as gradient.
        assert_eq!(db, dg, "{fig}: depth/coverage differs from gradient");
        assert_eq!(sb, sr, "{fig}");
        assert_eq!(sb.pixels, sg.pixels, "{fig}");
        assert_eq!(sb.drawn, sg.drawn, "{fig}");
    }
}

#[test]
fn strips_give_the_same_bytes_as_the_whole_frame() {
    // Odd strip heights move the pairing of rows into 2×2 blocks.
    for fig in FIGURES {
        let mut ls = load::load_arg(fig).unwrap();
        ls.desc.shading = ShadingName::QUADRATIC;
        let whole = render::render(&ls, None).unwrap().bytes;
        for rows in [1, 7, 32] {
            let strips = render::render(&ls, Some(rows)).unwrap().bytes;
            assert!(whole == strips, "{fig}: strips of {rows} rows differ");
        }
    }
}

#[test]
fn span_method_does_not_change_the_surface() {
    let mut ls = load::load_arg("sphere").unwrap();
    ls.desc.shading = ShadingName::QUADRATIC;
    let want = render::render(&ls, None).unwrap();
    for m in [
        SpanName::CLASSIC,
        SpanName::named("sierpinski"),
        SpanName::named("kway4"),
    ] {
        ls.desc.span = m;
        let got = render::render(&ls, None).unwrap();
        assert!(want.bytes == got.bytes, "{m:?}");
        assert_eq!(want.image.covered, got.image.covered, "{m:?}");
    }
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as u32
    }
    fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo) as u32) as i32
    }
}

const W: u32 = 96;
const H: u32 = 80;

fn random_triangle(rng: &mut Rng, size: i32) -> [ScreenVertex; 3] {
    let c = |rng: &mut Rng| [0; 3].map(|_| rng.range(0, 255 << 16));
    core::array::from_fn(|_| ScreenVertex {
        x: rng.range(-16 * size, 16 * (W as i32 + size)),
        y: rng.range(-16 * size, 16 * (H as i32 + size)),
        z: rng.next() % (0xFFF0 << 16),
        c: c(rng),
    })
}

type Buffers = (Vec<[u8; 3]>, Vec<u16>, u32);

fn run(f: impl FnOnce(&mut Framebuffer<Rgb888>) -> u32) -> Buffers {
    let n = (W * H) as usize;
    let mut color = vec![[7u8; 3]; n];
    let mut depth = vec![0xFFFFu16; n];
    let mut fb = Framebuffer::<Rgb888>::new(&mut color, Some(&mut depth), W, H).unwrap();
    let px = f(&mut fb);
    (color, depth, px)
}

#[test]
fn random_triangles_blocks_rows_and_coverage() {
    let mut rng = Rng(0x5eed_0003);
    let mut drawn = 0;
    for it in 0..3000 {
        let size = [4, 30, 200, 3000][it % 4];
        let v = random_triangle(&mut rng, size);
        let mid: [[i32; 3]; 3] = core::array::from_fn(|_| [0; 3].map(|_| rng.range(0, 255 << 16)));
        let rows = run(|fb| draw_quadratic::<Rgb888, _, DepthTest>(fb, v, mid, Fill::Rows));
        let blocks = run(|fb| draw_quadratic::<Rgb888, _, DepthTest>(fb, v, mid, Fill::Blocks));
        let grad = run(|fb| draw_triangle::<Rgb888, _, Gradient, DepthTest, Gouraud>(fb, v));
        assert!(rows.0 == blocks.0, "{v:?}: blocks differ from rows");
        assert_eq!(rows.2, blocks.2);
        // Coverage (and depth) exactly that of the gradient method.
        assert!(rows.1 == grad.1, "{v:?}: coverage differs from gradient");
        assert_eq!(rows.2, grad.2);
        drawn += (rows.2 > 0) as u32;
    }
    assert!(drawn > 1000, "{drawn}");
}

#[test]
fn planar_samples_reproduce_gouraud() {
    let mut rng = Rng(42);
    let mut worst = 0;
    for it in 0..3000 {
        let size = [4, 30, 200, 3000][it % 4];
        let v = random_triangle(&mut rng, size);
        // Midpoint samples on the plane of the vertex colours.
        let mid: [[i32; 3]; 3] = core::array::from_fn(|k| {
            let (a, b) = (v[k].c, v[(k + 1) % 3].c);
            core::array::from_fn(|ch| (a[ch] + b[ch]) / 2)
        });
        let q = run(|fb| draw_quadratic::<Rgb888, _, DepthTest>(fb, v, mid, Fill::Blocks));
        let g = run(|fb| draw_triangle::<Rgb888, _, Gradient, DepthTest, Gouraud>(fb, v));
        for (a, b) in q.0.iter().zip(&g.0) {
            for ch in 0..3 {
                worst = worst.max((a[ch] as i32 - b[ch] as i32).abs());
            }
        }
    }
    println!("planar samples: largest difference to Gouraud {worst} step(s)");
    assert!(worst <= 1, "{worst}");
}

#[test]
fn strip_targets_match_framebuffer() {
    // A single large triangle through strips of odd heights.
    let mut rng = Rng(9);
    for _ in 0..200 {
        let v = random_triangle(&mut rng, 200);
        let mid: [[i32; 3]; 3] = core::array::from_fn(|_| [0; 3].map(|_| rng.range(0, 255 << 16)));
        let whole = run(|fb| draw_quadratic::<Rgb888, _, DepthTest>(fb, v, mid, Fill::Blocks));
        let n = (W * H) as usize;
        let mut out = vec![[7u8; 3]; n];
        let rows = 5;
        let mut buf = vec![[7u8; 3]; (W * rows) as usize];
        let mut depth = vec![0xFFFFu16; (W * rows) as usize];
        let mut y0 = 0;
        while y0 < H {
            let hh = rows.min(H - y0);
            let mut s = Strip::<Rgb888>::new(&mut buf, Some(&mut depth), W, H, y0, hh).unwrap();
            s.clear([7; 3]);
            draw_quadratic::<Rgb888, _, DepthTest>(&mut s, v, mid, Fill::Blocks);
            let len = (W * hh) as usize;
            let at = (y0 * W) as usize;
            out[at..at + len].copy_from_slice(&s.color()[..len]);
            y0 += hh;
        }
        assert!(out == whole.0, "{v:?}");
    }
}

#[test]
fn clipped_triangles_fall_back_to_gouraud() {
    use fixshade::fixed::{Angle, Q16_16, Q2_14};
    use fixshade::geometry::Mesh;
    use fixshade::light::{Light, Material};
    use fixshade::scene::{Camera, Object, Placement, Projection, Scene};
    // One triangle far wider than the guard band: it goes through the clipper.
    static POS: [[Q16_16; 3]; 3] = [
        [Q16_16::from_int(-2000), Q16_16::from_int(-1), Q16_16::ZERO],
        [Q16_16::from_int(2000), Q16_16::from_int(-1), Q16_16::ZERO],
        [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
    ];
    static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
    static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
    let camera = Camera {
        eye: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)],
        target: [Q16_16::ZERO; 3],
        up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
        projection: Projection::Perspective {
            fovy: Angle::from_degrees(60),
            near: Q16_16::ONE,
            far: Q16_16::from_int(10),
        },
    };
    let mut scene = Scene::new(camera);
    let white = [Q16_16::ONE; 3];
    scene
        .add_light(Light::directional(
            [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE],
            white,
            white,
        ))
        .unwrap();
    let mesh = Mesh::new(&POS, &NRM, &TRI).unwrap();
    scene
        .add_object(Object {
            mesh,
            placement: Placement::default(),
            material: Material::default(),
            back_material: None,
        })
        .unwrap();
    let mut cache = [XfVertex::default(); 3];
    let frame = Frame::<Rgb888>::prepare(&scene, W, H, &mut cache).unwrap();
    let q = {
        let n = (W * H) as usize;
        let mut color = vec![[7u8; 3]; n];
        let mut depth = vec![0xFFFFu16; n];
        let mut fb = Framebuffer::<Rgb888>::new(&mut color, Some(&mut depth), W, H).unwrap();
        let st = frame
            .draw_with::<Gradient, DepthTest, QuadraticSurface, _>(&mut fb)
            .unwrap();
        (color, st)
    };
    // The scene's shading is Gouraud.
    let g = run(|fb| frame.draw::<Gradient, _>(fb).unwrap().pixels);
    assert_eq!(q.1.clipped, 1);
    assert_eq!(q.1.fallback, 1);
    assert_eq!(q.1.pixels, g.2);
    assert!(g.2 > 100, "{}", g.2);
    assert!(q.0 == g.0, "the fallback is the Gouraud render");
}
