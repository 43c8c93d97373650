//! Watertightness: triangles that share edges cover every pixel centre of their
//! union exactly once, with the top-left rule on the outside.
//!
//! * random grids: an N×M grid of jittered vertices inside an axis-aligned
//!   rectangle `[X0, X1) × [Y0, Y1)` (Q12.4), each cell split along a random
//!   diagonal; every pixel with `X0 <= 16x + 8 < X1` and `Y0 <= 16y + 8 < Y1` is
//!   written exactly once, every other pixel never. Small grids in a 192×128 frame
//!   and huge ones (coordinates out to ±4095 pixels) in 4096-wide strips.
//! * random convex fans: a convex polygon triangulated from a hull vertex and from
//!   an interior point. Centres strictly inside (exact orientation tests) must be
//!   written once, centres strictly outside never; centres exactly on the outer
//!   boundary are checked too, against the half-open rule of the boundary edges
//!   (the winding model of `fixshade_tests`).
//! * meshes: sphere (48×32, 32×20, 128×80), teapot and robot projected with the f64
//!   reference's matrices and snapped to 1/16 pixel, each triangle drawn into a
//!   front or a back counter by the sign of its snapped area; `front − back` must
//!   equal the winding number of all directed edges at every pixel, and front and
//!   back separately equal the model of the front and back triangles. The closed
//!   convex sphere also has `front = back ∈ {0, 1}` (except where snapping to 1/16
//!   pixel folds a silhouette sliver over its neighbour; the model has the same
//!   2s there).
//! * the full fixed-point pipeline (`Frame`: vertex stage, clipper, fans, raster)
//!   on closed spheres: 0 or 2 writes per pixel without culling and half of that
//!   with culling; spheres reaching past the guard band; and the camera inside a
//!   closed sphere, where every pixel is written exactly once although most
//!   triangles go through the near-plane and guard-band clipper.
//! * zero-area triangles and triangles outside the guard band draw nothing.
//!
//! Every check runs with both span methods (`Gradient`, `Classic`): coverage comes
//! from the edge walker, but a span method must still write every pixel it is given.

use fixshade::raster::span::{Classic, Gradient, NoDepth, SpanMethod};
use fixshade::raster::{draw_triangle, GUARD};
use fixshade::render::{Frame, XfVertex};
use fixshade::shade::Flat;
use fixshade::target::Strip;
use fixshade_sim::scene::convert::{core_scene, quantize_mesh, FixedMesh};
use fixshade_sim::scene::desc::{MeshData, SceneDesc};
use fixshade_sim::scene::load::{load_arg, LoadedScene};
use fixshade_tests::*;

/// Draws `tris` (Q12.4) with span method `S` into a counting strip covering `win`
/// of a frame `frame_height` rows tall. Returns the counts and the sum of the
/// pixel counts `draw_triangle` reported.
fn draw_counts<S: SpanMethod>(
    win: &Window,
    frame_height: u32,
    tris: &[[P2; 3]],
) -> (Vec<u16>, u64) {
    let mut buf = vec![0u16; win.len()];
    let mut strip = Strip::<Count>::new(
        &mut buf,
        None,
        win.width as u32,
        frame_height,
        win.y0 as u32,
        win.h as u32,
    )
    .expect("strip");
    let mut reported = 0u64;
    for t in tris {
        let v = t.map(|p| sv(p.0, p.1, [0; 3]));
        reported += draw_triangle::<Count, _, S, NoDepth, Flat>(&mut strip, v) as u64;
    }
    (buf, reported)
}

/// Checks counts against `want` for both span methods; also checks that the pixel
/// totals `draw_triangle` reports match what it wrote.
fn check_both(
    what: &str,
    win: &Window,
    frame_height: u32,
    tris: &[[P2; 3]],
    want: &[i32],
) -> Result<usize, String> {
    let mut n = 0;
    for (name, (got, reported)) in [
        ("gradient", draw_counts::<Gradient>(win, frame_height, tris)),
        ("classic", draw_counts::<Classic>(win, frame_height, tris)),
    ] {
        n += diff_counts(&format!("{what} [{name}]"), win, &got, want)?;
        let total: u64 = got.iter().map(|c| *c as u64).sum();
        if total != reported {
            return Err(format!(
                "{what} [{name}]: draw_triangle reported {reported} pixels but wrote {total}"
            ));
        }
    }
    Ok(n)
}

// ---------------------------------------------------------------- random grids

/// How grid lines and the border are placed.
#[derive(Clone, Copy, Debug)]
enum Snap {
    /// Anywhere (any subpixel).
    Any,
    /// On pixel centres (16k + 8).
    Centre,
    /// On pixel edges (16k).
    Edge,
}

fn snap(v: i32, s: Snap) -> i32 {
    match s {
        Snap::Any => v,
        Snap::Centre => (v & !15) + 8,
        Snap::Edge => v & !15,
    }
}

/// `n + 1` strictly increasing coordinates from `lo` to `hi` (both kept).
fn grid_lines(rng: &mut Rng, lo: i32, hi: i32, n: usize, s: Snap) -> Vec<i32> {
    assert!(hi - lo >= n as i32 * 16 || matches!(s, Snap::Any) && hi - lo >= n as i32);
    loop {
        let mut v: Vec<i32> = (1..n).map(|_| snap(rng.int(lo + 1, hi - 1), s)).collect();
        v.push(lo);
        v.push(hi);
        v.sort_unstable();
        v.dedup();
        if v.len() == n + 1 && v[0] == lo && v[n] == hi {
            return v;
        }
    }
}

/// A random grid over `[x0, x1) × [y0, y1)` with `n × m` cells, `jitter` in 0..=2
/// (none, small, up to just under half a cell), every cell split along a random
/// diagonal, vertex order shuffled. All triangles are non-degenerate and none is
/// folded over (all have the same orientation before shuffling).
#[allow(clippy::too_many_arguments)]
fn random_grid(
    rng: &mut Rng,
    x: (i32, i32),
    y: (i32, i32),
    n: usize,
    m: usize,
    lines: Snap,
    jitter: u32,
) -> Vec<[P2; 3]> {
    let cx = grid_lines(rng, x.0, x.1, n, lines);
    let cy = grid_lines(rng, y.0, y.1, m, lines);
    let jit = |rng: &mut Rng, c: &[i32], i: usize, fixed: bool| -> i32 {
        if fixed || jitter == 0 {
            return c[i];
        }
        let lo = (c[i] - c[i - 1] - 1) / 2;
        let hi = (c[i + 1] - c[i] - 1) / 2;
        let (lo, hi) = if jitter == 1 {
            (lo.min(3), hi.min(3))
        } else {
            (lo, hi)
        };
        c[i] + rng.int(-lo, hi)
    };
    let mut vert = vec![(0, 0); (n + 1) * (m + 1)];
    for j in 0..=m {
        for i in 0..=n {
            // The border stays on its rectangle: x fixed on the left and right
            // sides, y fixed on the top and bottom sides.
            let vx = jit(rng, &cx, i, i == 0 || i == n);
            let vy = jit(rng, &cy, j, j == 0 || j == m);
            vert[j * (n + 1) + i] = (vx, vy);
        }
    }
    let at = |i: usize, j: usize| vert[j * (n + 1) + i];
    let mut tris = Vec::with_capacity(2 * n * m);
    for j in 0..m {
        for i in 0..n {
            let (tl, tr, bl, br) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
            // Front-facing (negative area, y down) splits along either diagonal.
            let d1 = [[tl, bl, br], [tl, br, tr]];
            let d2 = [[tl, bl, tr], [tr, bl, br]];
            let ok = |d: &[[P2; 3]; 2]| d.iter().all(|t| area2(t[0], t[1], t[2]) < 0);
            let (a, b) = if rng.chance(1, 2) { (d1, d2) } else { (d2, d1) };
            let pair = if ok(&a) {
                a
            } else {
                assert!(ok(&b), "cell ({i},{j}) of a grid folds both ways: {a:?}");
                b
            };
            for mut t in pair {
                t.rotate_left(rng.below(3) as usize);
                if rng.chance(1, 2) {
                    t.swap(1, 2);
                }
                tris.push(t);
            }
        }
    }
    tris
}

/// Expected counts of a grid over `[x0, x1) × [y0, y1)`: 1 where the centre lies
/// inside the half-open rectangle.
fn rect_counts(win: &Window, x: (i32, i32), y: (i32, i32)) -> Vec<i32> {
    let mut want = vec![0; win.len()];
    for row in 0..win.h {
        let yc = 16 * (win.y0 + row as i32) + 8;
        if !(y.0 <= yc && yc < y.1) {
            continue;
        }
        for px in 0..win.width {
            let xc = 16 * px as i32 + 8;
            if x.0 <= xc && xc < x.1 {
                want[row * win.width + px] = 1;
            }
        }
    }
    want
}

fn random_snap(rng: &mut Rng) -> Snap {
    *rng.pick(&[Snap::Any, Snap::Any, Snap::Centre, Snap::Edge])
}

/// A border coordinate near `v` placed per `s`, kept inside the guard band.
fn border(v: i32, s: Snap) -> i32 {
    snap(v, s).clamp(-GUARD + 16, GUARD - 16)
}

#[test]
fn random_grids_small_frame() {
    let win = Window {
        width: 192,
        y0: 0,
        h: 128,
    };
    let mut rng = Rng::new(0x0061_21d5);
    let grids = scaled(4000, 2000);
    let (mut pixels, mut tris_total) = (0usize, 0usize);
    for g in 0..grids {
        let s = random_snap(&mut rng);
        let lines = if rng.chance(1, 3) {
            random_snap(&mut rng)
        } else {
            Snap::Any
        };
        let (n, m) = (rng.range(1, 12) as usize, rng.range(1, 12) as usize);
        // Cells from a fraction of a pixel to tens of pixels; the region may stick
        // out of the frame on any side.
        let cell = *rng.pick(&[2, 8, 24, 64, 160, 400]);
        let min_w = if matches!(lines, Snap::Any) {
            n.max(m) as i32 + 2
        } else {
            16 * n.max(m) as i32 + 16
        };
        let w = rng.int(min_w, min_w + cell * n as i32);
        let h = rng.int(min_w, min_w + cell * m as i32);
        let x0 = border(rng.int(-40 * 16, 200 * 16), s);
        let y0 = border(rng.int(-40 * 16, 130 * 16), s);
        let x = (x0, border(x0 + w, s).max(x0 + min_w));
        let y = (y0, border(y0 + h, s).max(y0 + min_w));
        let jitter = rng.below(3) as u32;
        let tris = random_grid(&mut rng, x, y, n, m, lines, jitter);
        let want = rect_counts(&win, x, y);
        let what = format!(
            "grid {g}: {n}x{m} cells over x {x:?} y {y:?}, {s:?}/{lines:?}, jitter {jitter}"
        );
        pixels += check_both(&what, &win, 128, &tris, &want).unwrap_or_else(|e| panic!("{e}"));
        tris_total += tris.len();
    }
    println!("small grids: {grids} grids, {tris_total} triangles, {pixels} pixel checks");
}

#[test]
fn random_grids_huge_coordinates_in_strips() {
    // A 4096-wide strip of a 4096-row frame, 6 rows tall, at the top, the middle
    // or the bottom of the frame; grids reach out to ±4095 pixels.
    let mut rng = Rng::new(0xb16_9e1d);
    let grids = scaled(800, 400);
    let (mut pixels, mut tris_total) = (0usize, 0usize);
    let lim = GUARD - 1;
    for g in 0..grids {
        let win = Window {
            width: 4096,
            y0: *rng.pick(&[0, 1, 2047, 3000, 4090]),
            h: 6,
        };
        let s = random_snap(&mut rng);
        let lines = if rng.chance(1, 3) {
            random_snap(&mut rng)
        } else {
            Snap::Any
        };
        let (n, m) = (rng.range(1, 24) as usize, rng.range(1, 24) as usize);
        let x0 = border(rng.int(-lim, 60 * 16), s);
        let x1 = border(rng.int(4000 * 16, lim), s);
        // Rows: the rectangle straddles the strip, or one of its sides lies inside.
        let yc = 16 * win.y0 + 48;
        let mut r = |a: i32, b: i32| rng.int(a.clamp(-lim, lim), b.clamp(-lim, lim));
        let (y0, y1) = match r(0, 2) {
            0 => (r(-lim, yc - 48), r(yc + 48, lim)),
            1 => (r(yc - 56, yc + 40), r(yc + 48, lim)),
            _ => (r(-lim, yc - 48), r(yc - 40, yc + 56)),
        };
        let (y0, y1) = (border(y0, s), border(y1, s));
        if y1 - y0 < 16 * m as i32 + 16 {
            continue;
        }
        let x = (x0, x1);
        let y = (y0, y1);
        let jitter = rng.below(3) as u32;
        let tris = random_grid(&mut rng, x, y, n, m, lines, jitter);
        let want = rect_counts(&win, x, y);
        let what = format!(
            "huge grid {g}: {n}x{m} cells over x {x:?} y {y:?}, strip rows {}.., {s:?}/{lines:?}, jitter {jitter}",
            win.y0
        );
        pixels += check_both(&what, &win, 4096, &tris, &want).unwrap_or_else(|e| panic!("{e}"));
        tris_total += tris.len();
    }
    println!("huge grids: {grids} grids, {tris_total} triangles, {pixels} pixel checks");
}

/// The grid checker is not a tautology: a triangle drawn twice, a triangle left out
/// and a triangle shifted by half a pixel are all caught.
#[test]
fn grid_checker_detects_wrong_coverage() {
    let win = Window {
        width: 64,
        y0: 0,
        h: 48,
    };
    let (x, y) = ((5 * 16 + 3, 58 * 16 + 11), (4 * 16 + 7, 44 * 16 + 1));
    let mut rng = Rng::new(7);
    let tris = random_grid(&mut rng, x, y, 6, 5, Snap::Any, 2);
    let want = rect_counts(&win, x, y);
    check_both("intact grid", &win, 48, &tris, &want).expect("the intact grid is watertight");

    // The biggest triangle, so that it certainly holds pixel centres.
    let big = (0..tris.len())
        .max_by_key(|&i| area2(tris[i][0], tris[i][1], tris[i][2]).abs())
        .unwrap();
    let mut twice = tris.clone();
    twice.push(tris[big]);
    let e = check_both("drawn twice", &win, 48, &twice, &want).unwrap_err();
    assert!(e.contains("got 2, want 1"), "{e}");

    let mut missing = tris.clone();
    missing.remove(big);
    let e = check_both("missing", &win, 48, &missing, &want).unwrap_err();
    assert!(e.contains("got 0, want 1"), "{e}");

    let mut shifted = tris.clone();
    shifted[big] = tris[big].map(|p| (p.0 + 8, p.1));
    check_both("shifted", &win, 48, &shifted, &want).unwrap_err();
}

// ---------------------------------------------------------------- convex fans

/// Convex hull (Andrew's monotone chain), every turn of the same sign, without
/// collinear points.
fn convex_hull(mut pts: Vec<P2>) -> Vec<P2> {
    pts.sort_unstable();
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: P2, a: P2, b: P2| area2(o, a, b);
    let mut lower: Vec<P2> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<P2> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// True if `p` lies strictly inside the convex polygon `h` (all turns the same way).
fn strictly_inside(h: &[P2], p: P2) -> bool {
    let s: Vec<i64> = (0..h.len())
        .map(|i| area2(h[i], h[(i + 1) % h.len()], p).signum())
        .collect();
    s.iter().all(|v| *v > 0) || s.iter().all(|v| *v < 0)
}

/// True if `p` lies strictly outside the convex polygon `h`.
fn strictly_outside(h: &[P2], p: P2) -> bool {
    let orient = area2(h[0], h[1], h[2]).signum();
    (0..h.len()).any(|i| area2(h[i], h[(i + 1) % h.len()], p).signum() == -orient)
}

struct FanStats {
    polygons: usize,
    triangles: usize,
    inside: usize,
    outside: usize,
    boundary: usize,
}

/// Checks the fans of one polygon against the exact model; counts pixel classes.
fn check_fan(
    what: &str,
    win: &Window,
    fh: u32,
    hull: &[P2],
    tris: &[[P2; 3]],
    st: &mut FanStats,
) -> Result<(), String> {
    let mut w = Winding::new(win.clone());
    for i in 0..hull.len() {
        w.edge(hull[i], hull[(i + 1) % hull.len()], 1);
    }
    let model = w.finish();
    let mut want = vec![0i32; win.len()];
    for (i, m) in model.iter().enumerate() {
        let p = (
            16 * (i % win.width) as i32 + 8,
            16 * (win.y0 + (i / win.width) as i32) + 8,
        );
        if strictly_inside(hull, p) {
            assert_eq!(
                m.abs(),
                1,
                "{what}: model says {m} strictly inside at {p:?}"
            );
            want[i] = 1;
            st.inside += 1;
        } else if strictly_outside(hull, p) {
            assert_eq!(*m, 0, "{what}: model says {m} strictly outside at {p:?}");
            st.outside += 1;
        } else {
            // Exactly on the outer boundary: the half-open rule decides.
            want[i] = m.abs();
            st.boundary += 1;
        }
    }
    check_both(what, win, fh, tris, &want)?;
    st.triangles += tris.len();
    Ok(())
}

fn fans_from(hull: &[P2], s: usize) -> Vec<[P2; 3]> {
    let k = hull.len();
    (1..k - 1)
        .map(|i| [hull[s], hull[(s + i) % k], hull[(s + i + 1) % k]])
        .collect()
}

fn run_fans(
    seed: u64,
    polys: usize,
    win: &Window,
    fh: u32,
    span: (i32, i32),
    sizes: &[i32],
) -> FanStats {
    let mut rng = Rng::new(seed);
    let mut st = FanStats {
        polygons: 0,
        triangles: 0,
        inside: 0,
        outside: 0,
        boundary: 0,
    };
    for p in 0..polys {
        let size = *rng.pick(sizes);
        let snapmode = random_snap(&mut rng);
        let cx = rng.int(span.0, span.1);
        let cy = rng.int(
            16 * win.y0 - size / 2,
            16 * (win.y0 + win.h as i32) + size / 2,
        );
        let k = rng.range(3, 40) as usize;
        let pts: Vec<P2> = (0..k)
            .map(|_| {
                let q = |c: i32, r: &mut Rng| {
                    snap(c + r.int(-size, size), snapmode).clamp(-GUARD + 16, GUARD - 16)
                };
                (q(cx, &mut rng), q(cy, &mut rng))
            })
            .collect();
        let hull = convex_hull(pts);
        if hull.len() < 3 {
            continue;
        }
        st.polygons += 1;
        let s = rng.below(hull.len() as u64) as usize;
        let what = format!(
            "polygon {p} ({} vertices) fanned from vertex {s}: {hull:?}",
            hull.len()
        );
        check_fan(&what, win, fh, &hull, &fans_from(&hull, s), &mut st)
            .unwrap_or_else(|e| panic!("{e}"));

        // A random interior point as the fan centre.
        let (xmin, xmax) = (
            hull.iter().map(|v| v.0).min().unwrap(),
            hull.iter().map(|v| v.0).max().unwrap(),
        );
        let (ymin, ymax) = (
            hull.iter().map(|v| v.1).min().unwrap(),
            hull.iter().map(|v| v.1).max().unwrap(),
        );
        let centre = (0..50)
            .map(|_| (rng.int(xmin, xmax), rng.int(ymin, ymax)))
            .find(|c| strictly_inside(&hull, *c));
        if let Some(c) = centre {
            let k = hull.len();
            let mut tris: Vec<[P2; 3]> = (0..k).map(|i| [c, hull[i], hull[(i + 1) % k]]).collect();
            for t in &mut tris {
                t.rotate_left(rng.below(3) as usize);
            }
            let what = format!("polygon {p} fanned from interior point {c:?}: {hull:?}");
            check_fan(&what, win, fh, &hull, &tris, &mut st).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    st
}

#[test]
fn random_convex_fans() {
    let win = Window {
        width: 160,
        y0: 0,
        h: 120,
    };
    let st = run_fans(
        0xfa45,
        scaled(3000, 1500),
        &win,
        120,
        (-200, 161 * 16),
        &[24, 200, 800, 1600, 3000],
    );
    println!(
        "fans: {} polygons, {} triangles; pixel checks: {} strictly inside, {} strictly outside, {} on the boundary (half-open rule)",
        st.polygons, st.triangles, st.inside, st.outside, st.boundary
    );
    assert!(
        st.boundary > 0,
        "no centre on a boundary: the snapped cases did not happen"
    );
}

#[test]
fn random_convex_fans_huge() {
    let win = Window {
        width: 4096,
        y0: 2040,
        h: 4,
    };
    let st = run_fans(
        0xfa46,
        scaled(400, 200),
        &win,
        4096,
        (0, 4095 * 16),
        &[16 * 4000, 16 * 1000, 16 * 100],
    );
    println!(
        "huge fans: {} polygons, {} triangles; pixel checks: {} strictly inside, {} strictly outside, {} on the boundary",
        st.polygons, st.triangles, st.inside, st.outside, st.boundary
    );
}

/// The fan checker is not a tautology: a fan with one triangle drawn twice fails.
#[test]
fn fan_checker_detects_double_cover() {
    let win = Window {
        width: 40,
        y0: 0,
        h: 40,
    };
    let hull = convex_hull(vec![(20, 30), (600, 40), (610, 500), (300, 620), (40, 400)]);
    let mut st = FanStats {
        polygons: 0,
        triangles: 0,
        inside: 0,
        outside: 0,
        boundary: 0,
    };
    let tris = fans_from(&hull, 0);
    check_fan("intact fan", &win, 40, &hull, &tris, &mut st).unwrap();
    assert!(st.inside > 100);
    let mut twice = tris.clone();
    twice.push(tris[1]);
    let e = check_fan("twice", &win, 40, &hull, &twice, &mut st).unwrap_err();
    assert!(e.contains("got 2, want 1"), "{e}");
    let mut missing = tris.clone();
    missing.remove(1);
    let e = check_fan("missing", &win, 40, &hull, &missing, &mut st).unwrap_err();
    assert!(e.contains("got 0, want 1"), "{e}");
}

// ---------------------------------------------------------------- single triangles

/// The sign convention of the winding model against the rasterizer: a single
/// random triangle gives +1 (front) or −1 (back) exactly on the pixels drawn.
#[test]
fn winding_model_matches_single_triangles() {
    let win = Window {
        width: 96,
        y0: 0,
        h: 80,
    };
    let mut rng = Rng::new(0x51_6e1e);
    let n = scaled(4000, 2000);
    let mut checked = 0;
    for i in 0..n {
        let size = *rng.pick(&[20, 200, 1500]);
        let (cx, cy) = (rng.int(-100, 97 * 16), rng.int(-100, 81 * 16));
        let s = random_snap(&mut rng);
        let t: [P2; 3] = std::array::from_fn(|_| {
            (
                snap(cx + rng.int(-size, size), s),
                snap(cy + rng.int(-size, size), s),
            )
        });
        let a = area2(t[0], t[1], t[2]);
        let mut w = Winding::new(win.clone());
        w.triangle(t, 1);
        let model = w.finish();
        let sign = -a.signum() as i32; // front (a < 0) → +1
        assert!(
            model.iter().all(|m| *m == 0 || *m == sign),
            "triangle {i} {t:?}: winding values outside {{0, {sign}}}"
        );
        let want: Vec<i32> = model.iter().map(|m| m.abs()).collect();
        checked += check_both(&format!("triangle {i} {t:?}"), &win, 80, &[t], &want)
            .unwrap_or_else(|e| panic!("{e}"));
    }
    println!("single triangles: {n} triangles, {checked} pixel checks");
}

#[test]
fn single_triangle_checker_detects_a_subpixel_shift() {
    // Edges through pixel centres: moving the triangle right by 1/16 pixel
    // uncovers the left column, whose centres lie exactly on the left edge.
    let win = Window {
        width: 8,
        y0: 0,
        h: 8,
    };
    let t = [(8, 8), (8, 8 + 64), (8 + 64, 8)];
    let mut w = Winding::new(win.clone());
    w.triangle(t, 1);
    let want: Vec<i32> = w.finish().iter().map(|m| m.abs()).collect();
    check_both("exact", &win, 8, &[t], &want).unwrap();
    let shifted = t.map(|p| (p.0 + 1, p.1));
    let e = check_both("shifted", &win, 8, &[shifted], &want).unwrap_err();
    assert!(e.contains("got 0, want 1"), "{e}");
}

/// Zero-area triangles and triangles with a vertex outside the guard band draw
/// nothing and report 0 pixels; the same triangles just inside the band draw.
#[test]
fn degenerate_and_out_of_guard_triangles_draw_nothing() {
    let win = Window {
        width: 64,
        y0: 0,
        h: 64,
    };
    let zero = vec![0i32; win.len()];
    let degenerate: [[P2; 3]; 4] = [
        [(8, 8), (8, 8), (8, 8)],
        [(8, 8), (500, 8), (900, 8)],
        [(8, 8), (8, 700), (8, 300)],
        [(0, 0), (320, 160), (640, 320)],
    ];
    for t in degenerate {
        check_both(&format!("degenerate {t:?}"), &win, 64, &[t], &zero).unwrap();
    }
    let g = GUARD;
    for (outside, inside) in [
        ([(g, 8), (8, 700), (8, 8)], [(g - 1, 8), (8, 700), (8, 8)]),
        (
            [(-g, 8), (800, 700), (800, 8)],
            [(-g + 1, 8), (800, 700), (800, 8)],
        ),
        ([(8, g), (700, 8), (8, 8)], [(8, g - 1), (700, 8), (8, 8)]),
        (
            [(8, -g), (700, 900), (8, 900)],
            [(8, -g + 1), (700, 900), (8, 900)],
        ),
    ] {
        check_both(
            &format!("outside the guard band {outside:?}"),
            &win,
            64,
            &[outside],
            &zero,
        )
        .unwrap();
        let (c, n) = draw_counts::<Gradient>(&win, 64, &[inside]);
        assert!(
            n > 100 && c.iter().all(|v| *v <= 1),
            "{inside:?} drew {n} pixels"
        );
    }
}

// ---------------------------------------------------------------- meshes

struct MeshCase {
    name: String,
    desc: SceneDesc,
    meshes: Vec<MeshData>,
}

fn case(ls: &LoadedScene) -> MeshCase {
    MeshCase {
        name: ls.name.clone(),
        desc: ls.desc.clone(),
        meshes: ls.meshes.clone(),
    }
}

fn big_sphere(width: u32, height: u32) -> MeshCase {
    let ls = load_arg("sphere").expect("sphere scene");
    let mut desc = ls.desc.clone();
    desc.width = width;
    desc.height = height;
    MeshCase {
        name: format!("sphere 128x80 at {width}x{height}"),
        desc,
        meshes: vec![quantize_mesh(&fixshade_sim::scene::mesh::sphere(128, 80))],
    }
}

/// What drawing a projected mesh gives: front and back counters, and the winding
/// model of all triangles, of the front ones only and of the back ones only.
struct MeshCounts {
    win: Window,
    front: Vec<u16>,
    back: Vec<u16>,
    model: Vec<i32>,
    model_front: Vec<i32>,
    model_back: Vec<i32>,
}

/// Draws a projected mesh into front and back counters (by the sign of the snapped
/// area) and evaluates the winding model.
fn signed_mesh_counts<S: SpanMethod>(c: &MeshCase, tris: &[[P2; 3]]) -> MeshCounts {
    let win = Window {
        width: c.desc.width as usize,
        y0: 0,
        h: c.desc.height as usize,
    };
    let front: Vec<[P2; 3]> = tris
        .iter()
        .copied()
        .filter(|t| area2(t[0], t[1], t[2]) < 0)
        .collect();
    let back: Vec<[P2; 3]> = tris
        .iter()
        .copied()
        .filter(|t| area2(t[0], t[1], t[2]) > 0)
        .collect();
    let (f, _) = draw_counts::<S>(&win, c.desc.height, &front);
    let (b, _) = draw_counts::<S>(&win, c.desc.height, &back);
    let model_of = |ts: &[[P2; 3]]| {
        let mut w = Winding::new(win.clone());
        for t in ts {
            w.triangle(*t, 1);
        }
        w.finish()
    };
    MeshCounts {
        model: model_of(tris),
        model_front: model_of(&front),
        model_back: model_of(&back).iter().map(|v| -v).collect(),
        win,
        front: f,
        back: b,
    }
}

fn check_mesh(c: &MeshCase, closed_convex: bool) -> usize {
    let p = project(&c.desc, &c.meshes);
    assert_eq!(p.skipped, 0, "{}: triangles outside the guard band", c.name);
    let mut checked = 0;
    let mut folds = 0;
    for span in ["gradient", "classic"] {
        let m = if span == "gradient" {
            signed_mesh_counts::<Gradient>(c, &p.tris)
        } else {
            signed_mesh_counts::<Classic>(c, &p.tris)
        };
        let win = &m.win;
        let signed: Vec<i32> = m
            .front
            .iter()
            .zip(&m.back)
            .map(|(f, b)| *f as i32 - *b as i32)
            .collect();
        let ok = |r: Result<usize, String>| r.unwrap_or_else(|e| panic!("{e}"));
        checked += ok(diff_counts(
            &format!("{} [{span}] front − back vs winding", c.name),
            win,
            &signed,
            &m.model,
        ));
        ok(diff_counts(
            &format!("{} [{span}] front vs model", c.name),
            win,
            &m.front,
            &m.model_front,
        ));
        ok(diff_counts(
            &format!("{} [{span}] back vs model", c.name),
            win,
            &m.back,
            &m.model_back,
        ));
        if closed_convex {
            // Closed: every edge is used twice in opposite directions, so the total
            // winding is 0 and front and back cover the same pixels. Convex: each
            // side covers the silhouette once, except where snapping to 1/16 pixel
            // folds a sliver at the silhouette over its neighbour (the model shows
            // those pixels as front count 2 as well).
            assert!(m.model.iter().all(|v| *v == 0), "{}: not closed", c.name);
            ok(diff_counts(
                &format!("{} [{span}] front vs back", c.name),
                win,
                &m.front,
                &m.back,
            ));
            let over: Vec<usize> = (0..m.front.len()).filter(|&i| m.front[i] > 1).collect();
            for &i in &over {
                assert!(
                    m.model_front[i] > 1,
                    "{} [{span}]: pixel {i} written {} times",
                    c.name,
                    m.front[i]
                );
            }
            assert!(
                m.front.iter().all(|v| *v <= 2),
                "{}: front counts above 2",
                c.name
            );
            assert!(m.front.contains(&1), "{}: nothing drawn", c.name);
            folds = over.len();
        }
    }
    println!(
        "{}: {} triangles, {checked} pixel checks{}",
        c.name,
        p.tris.len(),
        if closed_convex {
            format!(", {folds} pixels under silhouette folds made by snapping")
        } else {
            String::new()
        }
    );
    checked
}

#[test]
fn meshes_signed_coverage_equals_winding_number() {
    let mut total = 0;
    for name in ["sphere", "bench-sphere"] {
        total += check_mesh(&case(&load_arg(name).unwrap()), true);
    }
    total += check_mesh(&big_sphere(320, 240), true);
    total += check_mesh(&big_sphere(1024, 768), true);
    for name in ["teapot", "robot"] {
        total += check_mesh(&case(&load_arg(name).unwrap()), false);
    }
    println!("meshes: {total} pixel checks");
}

/// The mesh checker is not a tautology: one sphere triangle drawn twice, or put in
/// the wrong (back) counter, is caught.
#[test]
fn mesh_checker_detects_wrong_coverage() {
    let c = case(&load_arg("bench-sphere").unwrap());
    let p = project(&c.desc, &c.meshes);
    let big = (0..p.tris.len())
        .max_by_key(|&i| -area2(p.tris[i][0], p.tris[i][1], p.tris[i][2]))
        .unwrap();
    let honest = signed_mesh_counts::<Gradient>(&c, &p.tris);
    let signed = |m: &MeshCounts| -> Vec<i32> {
        m.front
            .iter()
            .zip(&m.back)
            .map(|(f, b)| *f as i32 - *b as i32)
            .collect()
    };
    diff_counts("honest", &honest.win, &signed(&honest), &honest.model).unwrap();

    // One triangle drawn twice.
    let mut tris = p.tris.clone();
    tris.push(p.tris[big]);
    let m = signed_mesh_counts::<Gradient>(&c, &tris);
    assert!(diff_counts("twice", &m.win, &signed(&m), &honest.model).is_err());
    assert!(diff_counts("twice", &m.win, &m.front, &m.back).is_err());

    // The biggest front triangle drawn into the back counter.
    let mut flipped = p.tris.clone();
    let t = flipped[big];
    flipped[big] = [t[0], t[2], t[1]];
    let m = signed_mesh_counts::<Gradient>(&c, &flipped);
    assert!(diff_counts("flipped", &m.win, &signed(&m), &honest.model).is_err());
}

/// Counts of the full fixed-point pipeline (vertex stage, clip & cull, raster) for
/// a scene, back faces culled or not.
fn pipeline_counts(
    desc: &SceneDesc,
    fixed: &[FixedMesh],
    cull: bool,
) -> (Vec<u16>, fixshade::render::Stats) {
    let mut desc = desc.clone();
    desc.cull_back = cull;
    let scene = core_scene(&desc, fixed).unwrap();
    let (w, h) = (desc.width, desc.height);
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<Count>::prepare(&scene, w, h, &mut cache).unwrap();
    let mut buf = vec![0u16; (w * h) as usize];
    let mut fb = fixshade::target::Framebuffer::<Count>::new(&mut buf, None, w, h).unwrap();
    let st = frame
        .draw_with::<Gradient, NoDepth, Flat, _>(&mut fb)
        .unwrap();
    (buf, st)
}

/// Checks a closed convex mesh through the pipeline: 0 or 2 writes per pixel
/// without culling, and exactly half of that with back faces culled.
fn check_closed(name: &str, desc: &SceneDesc, fixed: &[FixedMesh]) -> (usize, u32) {
    let (all, st) = pipeline_counts(desc, fixed, false);
    let (front, _) = pipeline_counts(desc, fixed, true);
    let w = desc.width as usize;
    let bad: Vec<usize> = (0..all.len())
        .filter(|&i| all[i] != 0 && all[i] != 2)
        .collect();
    assert!(
        bad.is_empty(),
        "{name}: {} pixels written neither 0 nor 2 times without culling, e.g. ({}, {}) = {}",
        bad.len(),
        bad[0] % w,
        bad[0] / w,
        all[bad[0]]
    );
    let bad = (0..all.len())
        .filter(|&i| front[i] as u32 * 2 != all[i] as u32)
        .count();
    assert_eq!(
        bad, 0,
        "{name}: front-only coverage is not half the two-sided one"
    );
    (all.iter().filter(|c| **c == 2).count(), st.clipped)
}

/// The full fixed-point pipeline on the closed convex spheres: without culling every
/// pixel is written 0 or 2 times, with back faces culled 0 or 1 times, on the same
/// pixels.
#[test]
fn pipeline_sphere_is_closed_and_watertight() {
    let mut scenes: Vec<LoadedScene> = ["sphere", "bench-sphere"]
        .iter()
        .map(|n| load_arg(n).unwrap())
        .collect();
    let mut ls = load_arg("sphere").unwrap();
    ls.name = "sphere 128x80".into();
    let m = quantize_mesh(&fixshade_sim::scene::mesh::sphere(128, 80));
    ls.fixed = vec![FixedMesh::from_mesh(&m).unwrap()];
    ls.meshes = vec![m];
    scenes.push(ls);
    for ls in &scenes {
        let (inside, _) = check_closed(&ls.name, &ls.desc, &ls.fixed);
        assert!(inside > 10000, "{}: only {inside} pixels covered", ls.name);
        println!(
            "{}: pipeline closed-mesh check over {} pixels",
            ls.name,
            ls.desc.width * ls.desc.height
        );
    }
}

/// A coarse random sphere with a random camera, for the clipping tests.
fn random_sphere_scene(rng: &mut Rng, inside: bool) -> (SceneDesc, Vec<FixedMesh>, String) {
    let mut d = load_arg("sphere").unwrap().desc;
    let (lon, lat) = (rng.int(4, 24) as u32, rng.int(3, 16) as u32);
    let m = quantize_mesh(&fixshade_sim::scene::mesh::sphere(lon, lat));
    let fixed = vec![FixedMesh::from_mesh(&m).unwrap()];
    let mut r = |s: f64| rng.int(-1000, 1000) as f64 / 1000.0 * s;
    let fovy;
    if inside {
        // Camera inside a sphere of radius 4: triangles beside and behind the eye
        // cross the near plane and the guard band.
        d.camera.eye = [r(1.0), r(1.0), r(1.0)];
        d.camera.target = [r(5.0), r(5.0), r(5.0)];
        d.objects[0].scale = 4.0;
        fovy = 20.0 + (r(1.0) + 1.0) * 50.0;
    } else {
        // Camera outside the unit sphere, looking at a point near its silhouette
        // through a narrow lens: the sphere is up to thousands of pixels across and
        // many triangles reach past the guard band.
        let dir = [r(1.0), r(1.0), r(1.0) + 1e-3];
        let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        let dist = 1.2 + (r(1.0) + 1.0) * 1.0;
        d.camera.eye = dir.map(|c| c / len * dist);
        d.camera.target = [r(1.0), r(1.0), r(1.0)];
        d.objects[0].scale = 1.0;
        fovy = 1.0 + (r(1.0) + 1.0) * 8.0;
    }
    d.camera.up = [r(1.0), 1.0, r(1.0)];
    d.camera.projection = fixshade_sim::scene::desc::Projection::Perspective {
        fovy_deg: fovy,
        near: 0.05,
        far: 20.0,
    };
    d.objects[0].translate = [0.0; 3];
    d.objects[0].rotate_deg = [r(180.0), r(180.0), r(180.0)];
    let d = fixshade_sim::scene::convert::quantize_scene(&d);
    let name = format!(
        "sphere {lon}x{lat}, eye {:?}, target {:?}, fovy {fovy:.1}",
        d.camera.eye, d.camera.target
    );
    (d, fixed, name)
}

/// Camera inside a closed sphere: every pixel is written exactly once, although most
/// triangles go through the near-plane and guard-band clipper and are fanned.
#[test]
fn pipeline_inside_closed_sphere_covers_every_pixel_once() {
    let mut rng = Rng::new(0x1451de);
    let n = scaled(400, 200);
    let mut clipped = 0;
    for i in 0..n {
        let (d, fixed, name) = random_sphere_scene(&mut rng, true);
        let (c, st) = pipeline_counts(&d, &fixed, false);
        clipped += st.clipped;
        let bad: Vec<usize> = (0..c.len()).filter(|&k| c[k] != 1).collect();
        let w = d.width as usize;
        assert!(
            bad.is_empty(),
            "case {i}, {name}: {} pixels not written exactly once, e.g. ({}, {}) = {}",
            bad.len(),
            bad[0] % w,
            bad[0] / w,
            c[bad[0]]
        );
    }
    assert!(clipped > n as u32 * 20, "too little clipping: {clipped}");
    println!(
        "inside spheres: {n} scenes, {} pixels, {clipped} clipped triangles",
        n * 76800
    );
}

/// Camera outside a closed sphere that reaches past the guard band: 0 or 2 writes
/// per pixel without culling, half of that with culling.
#[test]
fn pipeline_guard_band_sphere_is_watertight() {
    let mut rng = Rng::new(0x9a4d);
    let n = scaled(400, 200);
    let (mut covered, mut clipped) = (0, 0);
    for i in 0..n {
        let (d, fixed, name) = random_sphere_scene(&mut rng, false);
        let (c, cl) = check_closed(&format!("case {i}, {name}"), &d, &fixed);
        covered += c;
        clipped += cl;
    }
    assert!(clipped > 100, "too little clipping: {clipped}");
    println!(
        "guard-band spheres: {n} scenes, {covered} covered pixels, {clipped} clipped triangles"
    );
}
