//! The `Divide` seam in the pipeline: the classic span division and the setup
//! reciprocal through every divider. Coverage never depends on the divider (only
//! attribute values do), and each divider's colour error against `exact` stays
//! within the bound its documentation derives from its `max_error`:
//! `η = 2^(1−b) + (2E + 2)·2^b/2³⁰` relative, at most `η·256` output steps.

use fixshade::divide::{Divide, Exact, ShiftAdd, ShiftAddRounded, Table};
use fixshade::raster::span::{Classic, Gradient, NoDepth, SpanMethod, WithDivide};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::shade::Gouraud;
use fixshade::target::{Framebuffer, Rgb888};
use fixshade_sim::render;
use fixshade_sim::scene::desc::{DivideName, Named};
use fixshade_sim::scene::load;

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
const H: u32 = 72;

/// Triangles of every size, from slivers to ones far beyond the target, with
/// random vertex colours over the full range.
fn triangles() -> Vec<[ScreenVertex; 3]> {
    let mut rng = Rng(0xD1_71DE);
    (0..300)
        .map(|i| {
            let reach = [24, 160, 900, 5000, 40000][i % 5];
            let cx = rng.range(0, 16 * W as i32);
            let cy = rng.range(0, 16 * H as i32);
            [0; 3].map(|_| ScreenVertex {
                x: (cx + rng.range(-reach, reach)).clamp(-65535, 65535),
                y: (cy + rng.range(-reach, reach)).clamp(-65535, 65535),
                z: 0,
                c: [0; 3].map(|_| rng.range(0, 256 << 16)),
            })
        })
        .collect()
}

/// Each triangle drawn alone into its own frame (no depth, no overdraw between
/// triangles), all frames concatenated, with the pixel count of each draw.
fn render<S: SpanMethod>(tris: &[[ScreenVertex; 3]], flat_colour: bool) -> (Vec<[u8; 3]>, u64) {
    let n = (W * H) as usize;
    let mut all = Vec::with_capacity(n * tris.len());
    let mut count = 0u64;
    for t in tris {
        let mut t = *t;
        if flat_colour {
            // Every vertex the same colour: any divider draws exactly it, so the
            // pixels holding it are the coverage.
            for v in &mut t {
                v.c = [200 << 16; 3];
            }
        }
        let mut color = vec![[0u8; 3]; n];
        let mut fb = Framebuffer::<Rgb888>::new(&mut color, None, W, H).unwrap();
        count += draw_triangle::<Rgb888, _, S, NoDepth, Gouraud>(&mut fb, t) as u64;
        all.extend(color);
    }
    (all, count)
}

/// The relative error bound of a divider's wide reciprocal.
fn eta<D: Divide>() -> f64 {
    let b = D::mantissa_bits().clamp(1, 12) as i32;
    let e = D::max_error(1 << 30, 1 << b) as f64;
    2f64.powi(1 - b) + (2.0 * e + 2.0) * 2f64.powi(b) / 2f64.powi(30)
}

/// Coverage equal to `exact`'s and every channel within `⌊η·256 + 0.2⌋ + 1` steps
/// of it (0.2: the truncations both paths share; 1: the output rounding). Returns
/// the largest channel difference seen.
fn check<S: SpanMethod, E: SpanMethod, D: Divide>(what: &str, tris: &[[ScreenVertex; 3]]) -> u8 {
    let (cov_e, n_e) = render::<E>(tris, true);
    let (cov_d, n_d) = render::<S>(tris, true);
    assert_eq!(n_d, n_e, "{what} {}: pixel count differs", D::NAME);
    let miss = cov_e.iter().zip(&cov_d).filter(|(a, b)| a != b).count();
    assert_eq!(
        miss,
        0,
        "{what} {}: coverage differs at {miss} pixels",
        D::NAME
    );
    assert!(cov_e.contains(&[200; 3]));

    let (want, _) = render::<E>(tris, false);
    let (got, _) = render::<S>(tris, false);
    let bound = (eta::<D>() * 256.0 + 0.2).floor() as i32 + 1;
    let mut worst = 0u8;
    for (a, b) in want.iter().zip(&got) {
        for k in 0..3 {
            let d = (a[k] as i32 - b[k] as i32).unsigned_abs() as u8;
            worst = worst.max(d);
        }
    }
    assert!(
        (worst as i32) <= bound,
        "{what} {}: channel error {worst} above the bound {bound} (η = {:.3e})",
        D::NAME,
        eta::<D>()
    );
    println!(
        "{what:8} {:22} max channel error {worst:3} (bound {bound})",
        D::NAME
    );
    worst
}

macro_rules! every_divider {
    ($f:ident) => {{
        let mut w = vec![$f::<Table>()];
        w.push($f::<ShiftAdd<4>>());
        w.push($f::<ShiftAdd<5>>());
        w.push($f::<ShiftAdd<6>>());
        w.push($f::<ShiftAdd<7>>());
        w.push($f::<ShiftAdd<8>>());
        w.push($f::<ShiftAdd<9>>());
        w.push($f::<ShiftAdd<10>>());
        w.push($f::<ShiftAdd<11>>());
        w.push($f::<ShiftAdd<12>>());
        w.push($f::<ShiftAdd<13>>());
        w.push($f::<ShiftAdd<14>>());
        w.push($f::<ShiftAdd<15>>());
        w.push($f::<ShiftAdd<16>>());
        w.push($f::<ShiftAddRounded<4>>());
        w.push($f::<ShiftAddRounded<8>>());
        w.push($f::<ShiftAddRounded<12>>());
        w.push($f::<ShiftAddRounded<16>>());
        w
    }};
}

#[test]
fn classic_with_every_divider_keeps_coverage_within_its_bound() {
    fn one<D: Divide>() -> u8 {
        check::<Classic<D>, Classic, D>("classic", &triangles())
    }
    let worst = every_divider!(one);
    // The approximation is visible: the coarsest divider does change pixels, the
    // table only by the output rounding.
    assert!(worst[0] <= 1, "table: {}", worst[0]);
    assert!(worst[1] > 1, "shift-add-4 changed nothing");
}

#[test]
fn setup_reciprocal_with_every_divider_keeps_coverage_within_its_bound() {
    fn one<D: Divide>() -> u8 {
        check::<WithDivide<Gradient, D>, Gradient, D>("setup", &triangles())
    }
    let worst = every_divider!(one);
    assert!(worst[0] <= 1, "table: {}", worst[0]);
    assert!(worst[1] > 1, "shift-add-4 changed nothing");
}

#[test]
fn exact_wrapper_draws_the_plain_method() {
    // WithDivide<S, Exact> takes the setup's own full-precision reciprocal.
    let tris = triangles();
    assert_eq!(
        render::<WithDivide<Gradient, Exact>>(&tris, false),
        render::<Gradient>(&tris, false)
    );
    assert_eq!(
        render::<WithDivide<Classic, Exact>>(&tris, false),
        render::<Classic>(&tris, false)
    );
}

/// Sum of squared channel differences of two images.
fn squared_error(a: &[[u8; 3]], b: &[[u8; 3]]) -> u64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| (0..3).map(move |k| (x[k] as i64 - y[k] as i64).pow(2) as u64))
        .sum()
}

/// Through the host pipeline (the CLI's `--divide`): the figure keeps its coverage
/// with every divider, `exact` is the default render, and the error shrinks as N
/// grows.
#[test]
fn pipeline_dividers_on_the_sphere() {
    let mut ls = load::load_arg("sphere").unwrap();
    ls.desc.span = fixshade_sim::scene::desc::SpanName::CLASSIC;
    let base = render::render(&ls, None).unwrap();
    ls.desc.divide = DivideName::EXACT;
    assert_eq!(render::render(&ls, None).unwrap().bytes, base.bytes);
    let mut errs = Vec::new();
    for &(d, name) in DivideName::ALL {
        ls.desc.divide = d;
        let r = render::render(&ls, None).unwrap();
        assert_eq!(r.image.covered, base.image.covered, "{name}: coverage");
        assert_eq!(r.stats, base.stats, "{name}: draw statistics");
        let sq = squared_error(&r.image.pixels, &base.image.pixels);
        errs.push((name, sq));
    }
    let e = |n: &str| errs.iter().find(|x| x.0 == n).unwrap().1;
    assert_eq!(e("exact"), 0);
    assert!(e("shift-add-4") > e("shift-add-8"), "{errs:?}");
    assert!(e("shift-add-8") > e("shift-add-16"), "{errs:?}");
    assert!(e("shift-add-4") > 0);
}

/// The quadratic, Phong and adaptive paths take their setup's reciprocal through
/// the divider too (`SpanMethod::Divider`): on the sphere every divider keeps the
/// coverage and the draw statistics, `exact` is the default render, the coarsest
/// divider changes pixels and the error shrinks as N grows.
#[test]
fn per_pixel_shadings_take_the_divider() {
    use fixshade_sim::scene::desc::ShadingName;
    for shading in [
        ShadingName::QUADRATIC,
        ShadingName::PHONG,
        ShadingName::ADAPTIVE,
    ] {
        let mut ls = load::load_arg("sphere").unwrap();
        ls.desc.shading = shading;
        let base = render::render(&ls, None).unwrap();
        let mut errs = Vec::new();
        for name in [
            "exact",
            "table",
            "shift-add-4",
            "shift-add-8",
            "shift-add-16",
        ] {
            ls.desc.divide = DivideName::parse(name).unwrap();
            let r = render::render(&ls, None).unwrap();
            assert_eq!(
                r.image.covered, base.image.covered,
                "{shading:?} {name}: coverage"
            );
            assert_eq!(r.stats, base.stats, "{shading:?} {name}: draw statistics");
            let sq = squared_error(&r.image.pixels, &base.image.pixels);
            errs.push((name, sq));
        }
        let e = |n: &str| errs.iter().find(|x| x.0 == n).unwrap().1;
        println!("{shading:?}: squared error against exact {errs:?}");
        assert_eq!(e("exact"), 0, "{shading:?}");
        assert!(e("shift-add-4") > 0, "{shading:?}: the divider is not used");
        assert!(e("shift-add-4") > e("shift-add-8"), "{shading:?} {errs:?}");
        assert!(
            e("shift-add-8") >= e("shift-add-16"),
            "{shading:?} {errs:?}"
        );
        assert!(e("table") <= e("shift-add-8"), "{shading:?} {errs:?}");
    }
}

/// At the raster level: `draw_quadratic_div` and `draw_phong_div` with `Exact` draw
/// exactly what `draw_quadratic` and `draw_phong` draw, and every divider keeps
/// their coverage, on the same triangles as above (slivers to far beyond the
/// target).
#[test]
fn quadratic_and_phong_fills_keep_coverage_with_every_divider() {
    use fixshade::raster::phong::{draw_phong, draw_phong_div, PhongVertex, PixelLight, Rows};
    use fixshade::raster::quadratic::{draw_quadratic, draw_quadratic_div, Fill};

    /// Colour from the interpolated normal (any non-black value marks coverage).
    struct Normal;
    impl PixelLight for Normal {
        fn light(&self, _p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
            n.map(|c| (c >> 15).clamp(1 << 8, 1 << 15))
        }
    }
    fn phong_vertex(v: &ScreenVertex, k: usize) -> PhongVertex {
        let n = [
            [1 << 29, 1 << 28, 1 << 30],
            [-(1 << 29), 0, 1 << 30],
            [0, -(1 << 29), 1 << 29],
        ][k];
        PhongVertex {
            x: v.x,
            y: v.y,
            z: 0,
            n,
            p: [0; 3],
        }
    }
    fn frames(
        tris: &[[ScreenVertex; 3]],
        draw: impl Fn(&mut Framebuffer<'_, Rgb888>, [ScreenVertex; 3]) -> u32,
    ) -> (Vec<[u8; 3]>, u64) {
        let n = (W * H) as usize;
        let (mut all, mut count) = (Vec::new(), 0u64);
        for t in tris {
            let mut color = vec![[0u8; 3]; n];
            let mut fb = Framebuffer::<Rgb888>::new(&mut color, None, W, H).unwrap();
            count += draw(&mut fb, *t) as u64;
            all.extend(color);
        }
        (all, count)
    }
    fn covered(f: &[[u8; 3]]) -> Vec<bool> {
        f.iter().map(|p| *p != [0; 3]).collect()
    }
    // Edge midpoints bright, so a quadratic pixel is never black where covered.
    let mid = [[200 << 16; 3]; 3];
    let tris: Vec<[ScreenVertex; 3]> = triangles()
        .into_iter()
        .map(|t| {
            t.map(|v| ScreenVertex {
                c: [100 << 16; 3],
                ..v
            })
        })
        .collect();
    let quad = |fb: &mut Framebuffer<'_, Rgb888>, t| {
        draw_quadratic::<Rgb888, _, NoDepth>(fb, t, mid, Fill::Rows)
    };
    let phong = |fb: &mut Framebuffer<'_, Rgb888>, t: [ScreenVertex; 3]| {
        let v = [0, 1, 2].map(|k| phong_vertex(&t[k], k));
        draw_phong::<Rgb888, _, NoDepth, Rows, _>(fb, v, &Normal)
    };
    let (q_e, q_n) = frames(&tris, quad);
    let (p_e, p_n) = frames(&tris, phong);
    assert!(q_n > 0 && p_n > 0);
    fn one<D: Divide>(
        tris: &[[ScreenVertex; 3]],
        mid: [[i32; 3]; 3],
        q: &(Vec<[u8; 3]>, u64),
        p: &(Vec<[u8; 3]>, u64),
    ) -> u8 {
        let quad = |fb: &mut Framebuffer<'_, Rgb888>, t| {
            draw_quadratic_div::<Rgb888, _, NoDepth, D>(fb, t, mid, Fill::Rows)
        };
        let phong = |fb: &mut Framebuffer<'_, Rgb888>, t: [ScreenVertex; 3]| {
            let v = [0, 1, 2].map(|k| phong_vertex(&t[k], k));
            draw_phong_div::<Rgb888, _, NoDepth, Rows, D, _>(fb, v, &Normal)
        };
        let (qd, qn) = frames(tris, quad);
        let (pd, pn) = frames(tris, phong);
        assert_eq!(qn, q.1, "quadratic {}: pixel count", D::NAME);
        assert_eq!(pn, p.1, "phong {}: pixel count", D::NAME);
        assert!(
            covered(&qd) == covered(&q.0),
            "quadratic {}: coverage",
            D::NAME
        );
        assert!(covered(&pd) == covered(&p.0), "phong {}: coverage", D::NAME);
        if D::EXACT {
            assert!(
                qd == q.0 && pd == p.0,
                "exact through the seam changed pixels"
            );
        }
        let worst = |a: &[[u8; 3]], b: &[[u8; 3]]| {
            a.iter()
                .zip(b)
                .flat_map(|(x, y)| (0..3).map(move |k| x[k].abs_diff(y[k])))
                .max()
                .unwrap_or(0)
        };
        worst(&qd, &q.0).max(worst(&pd, &p.0))
    }
    let w: Vec<u8> = vec![
        one::<Exact>(&tris, mid, &(q_e.clone(), q_n), &(p_e.clone(), p_n)),
        one::<Table>(&tris, mid, &(q_e.clone(), q_n), &(p_e.clone(), p_n)),
        one::<ShiftAdd<4>>(&tris, mid, &(q_e.clone(), q_n), &(p_e.clone(), p_n)),
        one::<ShiftAdd<8>>(&tris, mid, &(q_e.clone(), q_n), &(p_e.clone(), p_n)),
        one::<ShiftAddRounded<12>>(&tris, mid, &(q_e.clone(), q_n), &(p_e.clone(), p_n)),
        one::<ShiftAdd<16>>(&tris, mid, &(q_e, q_n), &(p_e, p_n)),
    ];
    println!("largest channel difference against exact: {w:?}");
    assert_eq!(w[0], 0);
    assert!(w[2] > 0, "shift-add-4 changed nothing");
}
