//! Accuracy of Gouraud interpolation against exact rational interpolation, and of
//! the figures against the f64 reference renderer.
//!
//! * Random triangles up to 4095 pixels wide (and tall, cut by the strip), small
//!   ones and slivers, random vertex colours in `0..=255` with random fraction bits,
//!   drawn with both span methods into a 4096-wide strip of a recording format: at
//!   every covered pixel each channel integer `got` satisfies
//!   `|got − exact| < 1` and `0 <= got <= 255`, where `exact` is the barycentric
//!   interpolation (in f64, from exact integer weights) of the vertex colours at the
//!   pixel centre. Coverage must equal the exact top-left-rule coverage and be the
//!   same for both methods.
//! * The figures (sphere, teapot, robot), fixed-point against the f64 reference:
//!   NMSE <= 1e-5 and no coverage mismatch, for both span methods.

use fixshade::raster::span::{Classic, Gradient, NoDepth, SpanMethod};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::shade::Gouraud;
use fixshade::target::Strip;
use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::scene::desc::SpanName;
use fixshade_sim::scene::load::load_arg;
use fixshade_tests::*;

const WIDTH: usize = 4096;
const FRAME_H: u32 = 4096;

/// A 4096-wide strip of recorded pixels.
struct RecStrip {
    win: Window,
    buf: Vec<<Rec as fixshade::target::PixelFormat>::Raw>,
}

impl RecStrip {
    fn new(y0: i32, h: usize) -> RecStrip {
        RecStrip {
            win: Window {
                width: WIDTH,
                y0,
                h,
            },
            buf: vec![None; WIDTH * h],
        }
    }

    fn draw<S: SpanMethod>(&mut self, v: [ScreenVertex; 3]) -> u32 {
        let mut strip = Strip::<Rec>::new(
            &mut self.buf,
            None,
            WIDTH as u32,
            FRAME_H,
            self.win.y0 as u32,
            self.win.h as u32,
        )
        .expect("strip");
        draw_triangle::<Rec, _, S, NoDepth, Gouraud>(&mut strip, v)
    }
}

#[derive(Default, Debug)]
struct AccStats {
    triangles: usize,
    pixels: usize,
    max_err: f64,
}

/// Exact channel value (channel units) at the centre of pixel `(x, y)`.
fn exact(v: &[ScreenVertex; 3], area: i64, x: i32, y: i32, ch: usize) -> f64 {
    let p = (16 * x + 8, 16 * y + 8);
    let q = |i: usize| (v[i].x, v[i].y);
    let l = [
        area2(q(1), q(2), p),
        area2(q(2), q(0), p),
        area2(q(0), q(1), p),
    ];
    let num: i128 = (0..3).map(|i| l[i] as i128 * v[i].c[ch] as i128).sum();
    num as f64 / (area as f64 * 65536.0)
}

/// Draws `drawn` with both span methods and checks every pixel of the rows it can
/// touch against the exact coverage and colours of `truth` (normally the same
/// triangle; the checker's own tests pass a different one). Coverage is checked for
/// both methods, colours for `Gradient` and, if `classic` is true, for `Classic`.
fn check_triangle(
    a: &mut RecStrip,
    b: &mut RecStrip,
    truth: [ScreenVertex; 3],
    drawn: [ScreenVertex; 3],
    classic: bool,
    st: &mut AccStats,
) -> Result<(), String> {
    let ng = a.draw::<Gradient>(drawn);
    let nc = b.draw::<Classic>(drawn);
    let win = a.win.clone();
    // Rows the triangles can touch, inside the strip.
    let ys = truth.iter().chain(&drawn).map(|v| v.y);
    let (ymin, ymax) = (ys.clone().min().unwrap(), ys.max().unwrap());
    let r0 = (ceil_div(ymin as i64 - 8, 16) as i32).max(win.y0);
    let r1 = (ceil_div(ymax as i64 - 8, 16) as i32 + 1).min(win.y0 + win.h as i32);
    let area = area2(
        (truth[0].x, truth[0].y),
        (truth[1].x, truth[1].y),
        (truth[2].x, truth[2].y),
    );
    let mut result = Ok(());
    let mut covered = 0usize;
    if r0 < r1 {
        let sub = Window {
            width: WIDTH,
            y0: r0,
            h: (r1 - r0) as usize,
        };
        let mut w = Winding::new(sub.clone());
        w.triangle(truth.map(|v| (v.x, v.y)), 1);
        let model = w.finish();
        'rows: for row in 0..sub.h {
            let y = r0 + row as i32;
            let off = (y - win.y0) as usize * WIDTH;
            for x in 0..WIDTH {
                let (g, c) = (a.buf[off + x], b.buf[off + x]);
                let want = model[row * WIDTH + x] != 0;
                if g.is_some() != want || c.is_some() != want {
                    result = Err(format!(
                        "pixel ({x},{y}): covered gradient {} classic {}, exact {want}",
                        g.is_some(),
                        c.is_some()
                    ));
                    break 'rows;
                }
                let (Some(g), Some(c)) = (g, c) else { continue };
                covered += 1;
                for ch in 0..3 {
                    let e = exact(&truth, area, x as i32, y, ch);
                    let methods = [("gradient", g[ch]), ("classic", c[ch])];
                    for (name, got) in &methods[..if classic { 2 } else { 1 }] {
                        let got = *got;
                        let err = (got as f64 - e).abs();
                        st.max_err = st.max_err.max(err);
                        if !(err < 1.0 && (0..=255).contains(&got)) {
                            result = Err(format!(
                                "pixel ({x},{y}) channel {ch} [{name}]: got {got}, exact {e:.6}"
                            ));
                            break 'rows;
                        }
                    }
                }
            }
        }
        for row in 0..sub.h {
            let off = (r0 - win.y0) as usize * WIDTH + row * WIDTH;
            a.buf[off..off + WIDTH].fill(None);
            b.buf[off..off + WIDTH].fill(None);
        }
    }
    result?;
    if ng as usize != covered || nc as usize != covered {
        return Err(format!(
            "draw_triangle reported {ng} (gradient) and {nc} (classic) pixels, {covered} covered"
        ));
    }
    st.triangles += 1;
    st.pixels += covered;
    Ok(())
}

fn colour(rng: &mut Rng) -> [i32; 3] {
    std::array::from_fn(|_| match rng.below(8) {
        0 => 0,
        1 => 255 << 16,
        _ => rng.int(0, 255 << 16),
    })
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    /// Vertices anywhere across the width, y inside the strip (±a few rows).
    Wide,
    /// Vertices anywhere in the 4096×4096 frame; the strip sees a band of it.
    Tall,
    /// Up to 20 pixels.
    Small,
    /// Long and less than about a pixel thick.
    Sliver,
    /// Like `Sliver` but the third vertex within 2/16 pixel of the long edge: spans a
    /// tiny fraction of a pixel wide with colour gradients of 10⁵ steps per pixel.
    Hairline,
    /// Vertices anywhere in the guard band (±4095 pixels), so the frame's left and
    /// right sides cut the triangle.
    Guard,
}

fn random_triangle(rng: &mut Rng, kind: Kind, win: &Window) -> [ScreenVertex; 3] {
    let xmax = 4095 * 16 - 1;
    let (sy0, sy1) = (16 * win.y0, 16 * (win.y0 + win.h as i32));
    loop {
        let pts: [P2; 3] = match kind {
            Kind::Wide => std::array::from_fn(|_| (rng.int(0, xmax), rng.int(sy0 - 64, sy1 + 64))),
            Kind::Tall => std::array::from_fn(|_| (rng.int(0, xmax), rng.int(0, 4096 * 16 - 1))),
            Kind::Small => {
                let (cx, cy) = (rng.int(0, xmax), rng.int(sy0, sy1));
                let s = rng.int(1, 320);
                std::array::from_fn(|_| (cx + rng.int(-s, s), cy + rng.int(-s, s)))
            }
            Kind::Guard => {
                std::array::from_fn(|_| (rng.int(-65535, 65535), rng.int(sy0 - 2048, sy1 + 2048)))
            }
            Kind::Sliver | Kind::Hairline => {
                let a = (rng.int(0, xmax), rng.int(sy0 - 64, sy1 + 64));
                let b = if matches!(kind, Kind::Hairline) {
                    // Up to 256 pixels long.
                    (a.0 + rng.int(-4096, 4096), a.1 + rng.int(-4096, 4096))
                } else if rng.chance(1, 2) {
                    (rng.int(0, xmax), rng.int(sy0 - 64, sy1 + 64))
                } else {
                    (rng.int(0, xmax), rng.int(0, 4096 * 16 - 1))
                };
                // The third vertex close to a point of the segment a–b.
                let t = rng.below(1 << 16) as i64;
                let m = |p: i32, q: i32| (p as i64 + (q - p) as i64 * t / 65536) as i32;
                let r = if matches!(kind, Kind::Hairline) {
                    2
                } else {
                    24
                };
                let d = rng.int(-r, r);
                let e = rng.int(-r, r);
                [a, b, (m(a.0, b.0) + d, m(a.1, b.1) + e)]
            }
        };
        let inside = |p: &P2| match kind {
            Kind::Guard => p.0.abs() < 65536 && p.1.abs() < 65536,
            _ => (0..4096 * 16).contains(&p.0) && p.1.abs() < 65536,
        };
        if area2(pts[0], pts[1], pts[2]) != 0 && pts.iter().all(inside) {
            let mut t = pts.map(|p| sv(p.0, p.1, colour(rng)));
            if matches!(kind, Kind::Hairline) {
                // The far vertex contrasts with the long edge: the steepest
                // gradient across the hairline.
                t[1].c = t[0].c;
                t[2].c = t[0].c.map(|c| (255 << 16) - c);
            }
            return t;
        }
    }
}

fn run(kind: Kind, n: usize, seed: u64, h: usize, classic: bool) -> AccStats {
    let mut rng = Rng::new(seed);
    let mut st = AccStats::default();
    let y0 = rng.int(0, FRAME_H as i32 - h as i32);
    let mut a = RecStrip::new(y0, h);
    let mut b = RecStrip::new(y0, h);
    for i in 0..n {
        let t = random_triangle(&mut rng, kind, &a.win);
        check_triangle(&mut a, &mut b, t, t, classic, &mut st).unwrap_or_else(|e| {
            panic!(
                "{kind:?} triangle {i} {t:?} (strip rows {y0}..{}): {e}",
                y0 + h as i32
            )
        });
    }
    println!(
        "{kind:?}: {} triangles, {} covered pixels × 3 channels × {} methods, max |error| {:.4}",
        st.triangles,
        st.pixels,
        if classic { 2 } else { 1 },
        st.max_err
    );
    st
}

#[test]
fn wide_triangles() {
    run(Kind::Wide, scaled(200, 100), 0xacc1, 256, true);
}

#[test]
fn tall_triangles_cut_by_the_strip() {
    run(Kind::Tall, scaled(200, 100), 0xacc2, 200, true);
}

#[test]
fn small_triangles() {
    run(Kind::Small, scaled(30000, 12000), 0xacc3, 64, true);
}

#[test]
fn sliver_triangles() {
    run(Kind::Sliver, scaled(2000, 1000), 0xacc4, 128, true);
}

/// Triangles with vertices on the corners and sides of the guard band (±4095.94
/// pixels), seen through strips at the top, middle and bottom of a 4096-row frame.
#[test]
fn guard_band_corners() {
    let g = 65535;
    let pts = [
        (-g, -g),
        (g, -g),
        (g, g),
        (-g, g),
        (0, -g),
        (g, 0),
        (0, g),
        (-g, 0),
        (0, 0),
        (g, 7),
        (-3, g),
    ];
    let mut rng = Rng::new(0xc0a7);
    let mut st = AccStats::default();
    for y0 in [0, 2044, 4088] {
        let mut a = RecStrip::new(y0, 8);
        let mut b = RecStrip::new(y0, 8);
        for (i, p) in pts.iter().enumerate() {
            for (j, q) in pts.iter().enumerate().skip(i + 1) {
                for r in pts.iter().skip(j + 1) {
                    if area2(*p, *q, *r) == 0 {
                        continue;
                    }
                    let t = [*p, *q, *r].map(|v| sv(v.0, v.1, colour(&mut rng)));
                    check_triangle(&mut a, &mut b, t, t, true, &mut st)
                        .unwrap_or_else(|e| panic!("strip at row {y0}, triangle {t:?}: {e}"));
                }
            }
        }
    }
    println!(
        "guard corners: {} triangles, {} covered pixels, max |error| {:.4}",
        st.triangles, st.pixels, st.max_err
    );
}

/// Hairline slivers, colours checked for `Gradient` (coverage for both).
#[test]
fn hairline_triangles_gradient() {
    run(Kind::Hairline, scaled(4000, 2000), 0xacc6, 128, false);
}

/// Core bug: `Classic` misses the 1-step bound on spans much narrower than a pixel
/// (see `classic_narrow_span_colour_error` for one exact case).
#[test]
fn hairline_triangles_classic() {
    run(Kind::Hairline, scaled(4000, 2000), 0xacc6, 128, true);
}

/// One exact case of the `Classic` narrow-span error. At row 48 (centre y = 776
/// subpixels) the span runs from x = 2103.994 (edge A→C) to 2104.018 (edge A→B)
/// subpixels, 0.0015 pixel wide, and holds pixel 131 (centre 2104). Its colour is
/// 255·area(A, B, P)/area(A, B, C) = 138.43; the constant-gradient method gives
/// 138, `Classic` gives 140: the crossings are rounded to 2⁻¹⁶ pixel, which
/// across a span this narrow moves the interpolation weight by about 1 %, i.e. by
/// |ΔI|·2⁻¹⁶/w ≈ 1.6 steps with ΔI = 185 steps.
#[test]
fn classic_narrow_span_colour_error() {
    let t = [
        sv(2162, 536, [0; 3]),
        sv(1652, 2647, [0; 3]),
        sv(2082, 867, [255 << 16; 3]),
    ];
    let mut st = AccStats::default();
    let mut a = RecStrip::new(0, 64);
    let mut b = RecStrip::new(0, 64);
    check_triangle(&mut a, &mut b, t, t, false, &mut st).expect("Gradient is within bounds");
    check_triangle(&mut a, &mut b, t, t, true, &mut st).unwrap();
}

#[test]
fn guard_band_triangles() {
    run(Kind::Guard, scaled(200, 100), 0xacc5, 128, true);
}

fn depth_image<S: SpanMethod>(v: [ScreenVertex; 3], h: usize) -> (Vec<Option<[i32; 3]>>, Vec<u16>) {
    use fixshade::raster::span::DepthTest;
    let mut c = vec![None; WIDTH * h];
    let mut d = vec![0xFFFFu16; WIDTH * h];
    let mut strip =
        Strip::<Rec>::new(&mut c, Some(&mut d), WIDTH as u32, FRAME_H, 0, h as u32).unwrap();
    draw_triangle::<Rec, _, S, DepthTest, Gouraud>(&mut strip, v);
    (c, d)
}

/// Checks the depth buffer after drawing `t` alone: within 1 of the exact
/// barycentric depth (Q16.16 → u16) wherever the colour was written, untouched
/// elsewhere. Returns (pixels, max error).
fn check_depth<S: SpanMethod>(t: [ScreenVertex; 3], h: usize) -> Result<(usize, f64), String> {
    let area = area2((t[0].x, t[0].y), (t[1].x, t[1].y), (t[2].x, t[2].y));
    let (c, d) = depth_image::<S>(t, h);
    let (mut pixels, mut max_err) = (0, 0f64);
    for (k, (c, d)) in c.iter().zip(&d).enumerate() {
        let (x, y) = ((k % WIDTH) as i32, (k / WIDTH) as i32);
        if c.is_none() {
            if *d != 0xFFFF {
                return Err(format!("pixel ({x},{y}): depth written without colour"));
            }
            continue;
        }
        let p = (16 * x + 8, 16 * y + 8);
        let q = |j: usize| (t[j].x, t[j].y);
        let l = [
            area2(q(1), q(2), p),
            area2(q(2), q(0), p),
            area2(q(0), q(1), p),
        ];
        let num: i128 = (0..3).map(|j| l[j] as i128 * t[j].z as i128).sum();
        let e = num as f64 / (area as f64 * 65536.0);
        let err = (*d as f64 - e).abs();
        max_err = max_err.max(err);
        if err >= 1.0 {
            return Err(format!("pixel ({x},{y}): depth {d}, exact {e:.4}"));
        }
        pixels += 1;
    }
    Ok((pixels, max_err))
}

fn run_depth<S: SpanMethod>(n: usize) {
    let mut rng = Rng::new(0xde97);
    let h = 96;
    let (mut pixels, mut max_err) = (0usize, 0f64);
    for i in 0..n {
        let kind = *rng.pick(&[Kind::Wide, Kind::Small, Kind::Sliver, Kind::Guard]);
        let win = Window {
            width: WIDTH,
            y0: 0,
            h,
        };
        let mut t = random_triangle(&mut rng, kind, &win);
        for v in &mut t {
            v.z = match rng.below(4) {
                0 => 0,
                1 => 65534 << 16,
                _ => rng.below((65534u64 << 16) + 1) as u32,
            };
        }
        let (p, e) = check_depth::<S>(t, h)
            .unwrap_or_else(|e| panic!("{} triangle {i} {t:?}: {e}", S::NAME));
        pixels += p;
        max_err = max_err.max(e);
    }
    println!(
        "depth [{}]: {n} triangles, {pixels} pixel checks, max |error| {max_err:.4}",
        S::NAME
    );
}

/// Depth: the u16 written is the exact barycentric depth rounded (within 1), for
/// vertex depths anywhere in the Q16.16 range `0..=65534·2¹⁶`.
#[test]
fn depth_interpolation_gradient() {
    run_depth::<Gradient>(scaled(400, 200));
}

/// Core bug, the depth side of `classic_narrow_span_colour_error`: on a sliver
/// with a depth gradient of about 10⁵ steps per pixel `Classic` writes depth 2116
/// at pixel (2649, 92) where the exact depth is 2114.89.
#[test]
fn depth_interpolation_classic() {
    let t = [
        ScreenVertex {
            x: 42200,
            y: 398,
            z: 0,
            c: [0; 3],
        },
        ScreenVertex {
            x: 48639,
            y: 36680,
            z: 65534 << 16,
            c: [0; 3],
        },
        ScreenVertex {
            x: 46102,
            y: 22406,
            z: 65534 << 16,
            c: [0; 3],
        },
    ];
    check_depth::<Gradient>(t, 96).expect("Gradient is within bounds");
    check_depth::<Classic>(t, 96).unwrap();
    run_depth::<Classic>(scaled(400, 200));
}

/// The checker is not a tautology: a colour off by 2 at one vertex, or a triangle
/// moved by 1/16 pixel off pixel centres, is caught.
#[test]
fn accuracy_checker_detects_errors() {
    let mut a = RecStrip::new(0, 64);
    let mut b = RecStrip::new(0, 64);
    let mut st = AccStats::default();
    let t = [
        sv(8, 8, [0; 3]),
        sv(8, 8 + 16 * 40, [100 << 16, 0, 255 << 16]),
        sv(8 + 16 * 50, 8, [200 << 16, 50 << 16, 0]),
    ];
    check_triangle(&mut a, &mut b, t, t, true, &mut st).unwrap();
    assert!(st.pixels > 500);
    let mut brighter = t;
    brighter[1].c[0] += 2 << 16;
    let e = check_triangle(&mut a, &mut b, t, brighter, true, &mut st).unwrap_err();
    assert!(e.contains("channel 0"), "{e}");
    let shifted = t.map(|v| ScreenVertex { x: v.x + 1, ..v });
    let e = check_triangle(&mut a, &mut b, t, shifted, true, &mut st).unwrap_err();
    assert!(
        e.contains("covered gradient false classic false, exact true"),
        "{e}"
    );
}

/// Fixed point against the f64 reference on the figures, both span methods.
#[test]
fn figures_match_the_reference() {
    for name in FIGURES {
        let mut ls = load_arg(name).unwrap();
        let reference = render::reference(&ls, false);
        for span in [SpanName::GRADIENT, SpanName::CLASSIC] {
            ls.desc.span = span;
            let r = render::render(&ls, None).unwrap();
            let c = compare(&reference, &r.image).unwrap();
            println!(
                "{name} {span:?}: NMSE {:.3e}, max channel error {}, coverage mismatch {}, {} covered pixels",
                c.nmse,
                c.max_channel_error,
                c.coverage_mismatch,
                r.image.covered_count()
            );
            assert!(
                r.image.covered_count() > 5000,
                "{name}: almost nothing drawn"
            );
            assert!(c.nmse <= 1e-5, "{name} {span:?}: NMSE {:e} > 1e-5", c.nmse);
            assert_eq!(
                c.coverage_mismatch, 0,
                "{name} {span:?}: coverage differs from the reference"
            );
        }
    }
}

/// A closed model with culling off (its far half is drawn and must lose the depth
/// test) seen with a near plane of 1e-4: with 32-bit depth cells the frame matches
/// the f64 reference (NMSE ≤ 1e-5, no coverage mismatch); with 16-bit cells the far
/// half shows through (NMSE above 1e-4), which is what the wider cells are for. The
/// teapot (near 1, far 10, 32-bit depth) is checked by `figures_match_the_reference`.
#[test]
fn closed_model_at_a_tiny_near_plane_matches_the_reference_with_32_bit_depth() {
    use fixshade_sim::scene::desc::Projection;
    let mut ls = load_arg("sphere").unwrap();
    ls.desc.cull_back = false;
    match &mut ls.desc.camera.projection {
        Projection::Perspective { near, .. } => *near = 1e-4,
        p => panic!("the sphere scene has a perspective camera, found {p:?}"),
    }
    let reference = render::reference(&ls, false);
    let mut nmse = [0.0; 2];
    for (k, bits) in [16, 32].into_iter().enumerate() {
        ls.desc.depth_bits = bits;
        let r = render::render(&ls, None).unwrap();
        let c = compare(&reference, &r.image).unwrap();
        println!(
            "depth {bits} bits: NMSE {:.3e}, max channel error {}",
            c.nmse, c.max_channel_error
        );
        assert_eq!(c.coverage_mismatch, 0, "{bits}-bit depth: coverage differs");
        nmse[k] = c.nmse;
    }
    assert!(nmse[1] <= 1e-5, "32-bit depth: NMSE {:e} > 1e-5", nmse[1]);
    assert!(
        nmse[0] > 1e-4,
        "16-bit depth: NMSE {:e}, expected the far half to show",
        nmse[0]
    );
}
