//! Rasterizes arbitrary triangles (any `i32` coordinates, any attributes, any span
//! method and shading) into a small target with a guard region around it.
//!
//! Input layout (little-endian), so seeds can be written from the catalogue:
//! byte 0 span method (bits 0–5: index into `SpanName::ALL`, modulo; bit 7 set: the
//! Phong fills instead, the vertex colour words as the Q2.30 normal and the first
//! three midpoint words as the eye position, any values), byte 1 flags (bit 0 depth
//! test, bit 1 strip instead of the whole frame, bits 2–3 shading: flat, Gouraud,
//! quadratic blocks, quadratic rows; bits 4–5 coordinate mode: raw, folded into the
//! guard band, folded around the target, on the pixel grid; bits 6–7 pixel format:
//! recorder, Rgb565Le, Rgb888, Gray8), byte 2 width − 1, byte 3 frame height − 1,
//! bytes 4–5 strip start and height; then up to 4 triangles of 108 bytes: three
//! vertices (x, y: i32, z: u32, colour: 3 × i32) and three edge-midpoint colours.
//!
//! Asserted: no panic (overflow checks are on), no row outside the target asked
//! for and no guard pixel changed; for every span method but the vertex-snapping
//! `sierpinski`, each triangle covers exactly the pixels of the exact top-left
//! coverage model (none when a vertex is outside the guard band) and reports that
//! many; `sierpinski` writes no pixel twice; the quadratic fills cover what
//! `gradient` covers, and so does the perspective fill (the first midpoint colour
//! word as the vertices' w; nothing drawn when one is not positive); with vertex
//! colours in range, recorded channels stay in range.
//! Phong: both fills cover exactly what `gradient` covers (without depth), the
//! even/odd fill equals the row fill, recorded channels stay in range; the
//! perspective-correct Phong fill (the second midpoint word triple as the vertices'
//! w, any values; per pixel and by 16-pixel sub-spans, with the exact and a 4-term
//! divider) writes nothing outside, keeps channels in range and covers exactly what
//! the affine fill covers (nothing when a w is not positive).
#![no_main]

use fixshade::divide::{Exact, ShiftAdd};
use fixshade::raster::perspective::{
    draw_phong_perspective, draw_triangle_perspective, Perspective,
};
use fixshade::raster::phong::{draw_phong, EvenOddPixels, PhongVertex, Rows};
use fixshade::raster::quadratic::{draw_quadratic, Fill};
use fixshade::raster::span::{DepthTest, NoDepth};
use fixshade::raster::{draw_triangle, ScreenVertex, GUARD};
use fixshade::shade::{Flat, Gouraud};
use fixshade::target::{Gray8, PixelFormat, Rgb565Le, Rgb888};
use fixshade_sim::scene::desc::{Named, SpanName};
use fixshade_sim::with_span_method;
use fixshade_tests::hard::NormalLight;
use fixshade_tests::{Count, Guarded, Rec, Winding};
use libfuzzer_sys::fuzz_target;

const MAX_W: u32 = 24;
const MAX_H: u32 = 24;

struct Case {
    phong: bool,
    span: SpanName,
    depth: bool,
    strip: (u32, u32),
    shading: u8,
    format: u8,
    w: u32,
    fh: u32,
    tris: Vec<([ScreenVertex; 3], [[i32; 3]; 3])>,
}

fn word(b: &[u8], i: usize) -> i32 {
    i32::from_le_bytes([b[4 * i], b[4 * i + 1], b[4 * i + 2], b[4 * i + 3]])
}

fn fold(v: i32, lo: i32, span: i32) -> i32 {
    lo + v.rem_euclid(span)
}

fn parse(data: &[u8]) -> Option<Case> {
    if data.len() < 6 {
        return None;
    }
    let span = SpanName::ALL[(data[0] & 0x3F) as usize % SpanName::ALL.len()].0;
    let flags = data[1];
    let w = (data[2] as u32 % MAX_W) + 1;
    let fh = (data[3] as u32 % MAX_H) + 1;
    let y0 = data[4] as u32 % fh;
    let h = (data[5] as u32 % (fh - y0)) + 1;
    let strip = if flags & 2 != 0 { (y0, h) } else { (0, fh) };
    let mode = (flags >> 4) & 3;
    let tris = data[6..]
        .chunks_exact(108)
        .take(4)
        .map(|t| {
            let v: [ScreenVertex; 3] = core::array::from_fn(|k| {
                let (x, y) = (word(t, 6 * k), word(t, 6 * k + 1));
                let (wx, wy) = (16 * w as i32, 16 * fh as i32);
                let (x, y) = match mode {
                    0 => (x, y),
                    1 => (
                        fold(x, -GUARD - 32, 2 * GUARD + 64),
                        fold(y, -GUARD - 32, 2 * GUARD + 64),
                    ),
                    2 => (fold(x, -128, wx + 256), fold(y, -128, wy + 256)),
                    _ => (
                        8 * fold(x, -8, 2 * w as i32 + 16),
                        8 * fold(y, -8, 2 * fh as i32 + 16),
                    ),
                };
                ScreenVertex {
                    x,
                    y,
                    z: word(t, 6 * k + 2) as u32,
                    c: [word(t, 6 * k + 3), word(t, 6 * k + 4), word(t, 6 * k + 5)],
                }
            });
            let mid = core::array::from_fn(|k| core::array::from_fn(|c| word(t, 18 + 3 * k + c)));
            (v, mid)
        })
        .collect();
    Some(Case {
        phong: data[0] & 0x80 != 0,
        span,
        depth: flags & 1 != 0,
        strip,
        shading: (flags >> 2) & 3,
        format: flags >> 6,
        w,
        fh,
        tris,
    })
}

fn in_guard(v: &[ScreenVertex; 3]) -> bool {
    v.iter()
        .all(|p| p.x.unsigned_abs() < GUARD as u32 && p.y.unsigned_abs() < GUARD as u32)
}

/// Coverage of one triangle against the exact model.
fn coverage(c: &Case, v: &[ScreenVertex; 3], mid: &[[i32; 3]; 3]) {
    let new = || Guarded::<Count>::new(c.w, c.fh, c.strip.0, c.strip.1, false, 0, 0);
    let mut g = new();
    let n = with_span_method!(c.span, S => draw_triangle::<Count, _, S, NoDepth, Flat>(&mut g, *v));
    assert!(g.intact(), "write outside the target");
    let got = g.pixels();
    let total: u32 = got.iter().map(|p| *p as u32).sum();
    assert_eq!(total, n, "reported {n} pixels, wrote {total}");
    let mut wind = Winding::new(g.window());
    if in_guard(v) {
        wind.triangle(v.map(|p| (p.x, p.y)), 1);
    }
    let want: Vec<u16> = wind
        .finish()
        .iter()
        .map(|w| w.unsigned_abs() as u16)
        .collect();
    if c.span == SpanName::named("sierpinski") {
        assert!(got.iter().all(|p| *p <= 1), "a pixel written twice");
    } else {
        assert_eq!(got, want, "coverage differs from the exact model");
    }
    // The quadratic fills cover what `gradient` covers.
    for fill in [Fill::Blocks, Fill::Rows] {
        let mut q = new();
        let nq = draw_quadratic::<Count, _, NoDepth>(&mut q, *v, *mid, fill);
        assert!(q.intact(), "quadratic: write outside the target");
        let got = q.pixels();
        let total: u32 = got.iter().map(|p| *p as u32).sum();
        assert_eq!(total, nq, "quadratic reported {nq} pixels, wrote {total}");
        assert_eq!(got, want, "quadratic coverage differs from the exact model");
    }
    // The perspective fill (the first midpoint colour as the vertices' w) covers
    // what `gradient` covers, per pixel and by sub-spans, with the exact and a
    // 4-term divider; nothing when a w is not positive.
    let w = mid[0].map(|x| x as i64);
    let none = vec![0u16; want.len()];
    let expect = if w.iter().all(|x| *x > 0) {
        &want
    } else {
        &none
    };
    for mode in [Perspective::PER_PIXEL, Perspective::SUB16] {
        for exact in [true, false] {
            let mut p = new();
            let np = if exact {
                draw_triangle_perspective::<Count, _, NoDepth, Gouraud, Exact>(&mut p, *v, w, mode)
            } else {
                draw_triangle_perspective::<Count, _, NoDepth, Gouraud, ShiftAdd<4>>(
                    &mut p, *v, w, mode,
                )
            };
            assert!(p.intact(), "perspective: write outside the target");
            let got = p.pixels();
            let total: u32 = got.iter().map(|p| *p as u32).sum();
            assert_eq!(total, np, "perspective reported {np} pixels, wrote {total}");
            assert_eq!(
                &got, expect,
                "perspective coverage differs from the exact model"
            );
        }
    }
}

fn colour<P: PixelFormat>(c: &Case, clear: P::Raw, sentinel: P::Raw) -> Guarded<P> {
    let mut g = Guarded::<P>::new(c.w, c.fh, c.strip.0, c.strip.1, c.depth, clear, sentinel);
    for (v, mid) in &c.tris {
        with_span_method!(c.span, S => match (c.shading, c.depth) {
            (0, false) => draw_triangle::<P, _, S, NoDepth, Flat>(&mut g, *v),
            (0, true) => draw_triangle::<P, _, S, DepthTest, Flat>(&mut g, *v),
            (1, false) => draw_triangle::<P, _, S, NoDepth, Gouraud>(&mut g, *v),
            (1, true) => draw_triangle::<P, _, S, DepthTest, Gouraud>(&mut g, *v),
            (2, false) => draw_quadratic::<P, _, NoDepth>(&mut g, *v, *mid, Fill::Blocks),
            (2, true) => draw_quadratic::<P, _, DepthTest>(&mut g, *v, *mid, Fill::Blocks),
            (_, false) => draw_quadratic::<P, _, NoDepth>(&mut g, *v, *mid, Fill::Rows),
            (_, true) => draw_quadratic::<P, _, DepthTest>(&mut g, *v, *mid, Fill::Rows),
        });
    }
    assert!(g.intact(), "write outside the target");
    g
}

/// The Phong fills on every triangle: coverage as `gradient`, even/odd = rows.
fn phong(c: &Case) {
    for (v, mid) in &c.tris {
        let pv = core::array::from_fn::<_, 3, _>(|k| PhongVertex {
            x: v[k].x,
            y: v[k].y,
            z: v[k].z,
            n: v[k].c,
            p: mid[0],
        });
        let new = || {
            Guarded::<Rec>::new(
                c.w,
                c.fh,
                c.strip.0,
                c.strip.1,
                c.depth,
                None,
                Some([i32::MIN; 3]),
            )
        };
        let (mut rows, mut eo) = (new(), new());
        let n = if c.depth {
            draw_phong::<Rec, _, DepthTest, Rows, _>(&mut rows, pv, &NormalLight);
            draw_phong::<Rec, _, DepthTest, EvenOddPixels, _>(&mut eo, pv, &NormalLight)
        } else {
            draw_phong::<Rec, _, NoDepth, Rows, _>(&mut rows, pv, &NormalLight);
            draw_phong::<Rec, _, NoDepth, EvenOddPixels, _>(&mut eo, pv, &NormalLight)
        };
        assert!(
            rows.intact() && eo.intact(),
            "phong: write outside the target"
        );
        assert_eq!(
            rows.pixels(),
            eo.pixels(),
            "phong: even/odd differs from rows"
        );
        for p in rows.pixels().into_iter().flatten() {
            assert!(
                p.iter().all(|ch| (0..=255).contains(ch)),
                "phong: channel out of range: {p:?}"
            );
        }
        if !c.depth {
            let mut g = Guarded::<Count>::new(c.w, c.fh, c.strip.0, c.strip.1, false, 0, 0);
            draw_triangle::<Count, _, fixshade::raster::span::Gradient, NoDepth, Flat>(&mut g, *v);
            let want: Vec<bool> = g.pixels().iter().map(|p| *p > 0).collect();
            let got: Vec<bool> = rows.pixels().iter().map(|p| p.is_some()).collect();
            assert_eq!(got, want, "phong: coverage differs from gradient");
            assert_eq!(
                got.iter().filter(|b| **b).count() as u32,
                n,
                "phong: reported count"
            );
        }
        // The perspective-correct fill covers what the affine fill covers.
        let w = mid[1].map(|x| x as i64);
        let affine: Vec<bool> = rows.pixels().iter().map(|p| p.is_some()).collect();
        let expect = if w.iter().all(|x| *x > 0) {
            affine
        } else {
            vec![false; affine.len()]
        };
        for mode in [Perspective::PER_PIXEL, Perspective::SUB16] {
            for exact in [true, false] {
                let mut p = new();
                let np = match (c.depth, exact) {
                    (false, true) => draw_phong_perspective::<Rec, _, NoDepth, Exact, _>(
                        &mut p,
                        pv,
                        w,
                        mode,
                        &NormalLight,
                    ),
                    (false, false) => draw_phong_perspective::<Rec, _, NoDepth, ShiftAdd<4>, _>(
                        &mut p,
                        pv,
                        w,
                        mode,
                        &NormalLight,
                    ),
                    (true, true) => draw_phong_perspective::<Rec, _, DepthTest, Exact, _>(
                        &mut p,
                        pv,
                        w,
                        mode,
                        &NormalLight,
                    ),
                    (true, false) => draw_phong_perspective::<Rec, _, DepthTest, ShiftAdd<4>, _>(
                        &mut p,
                        pv,
                        w,
                        mode,
                        &NormalLight,
                    ),
                };
                assert!(p.intact(), "phong perspective: write outside the target");
                for px in p.pixels().into_iter().flatten() {
                    assert!(
                        px.iter().all(|ch| (0..=255).contains(ch)),
                        "phong perspective: channel out of range: {px:?}"
                    );
                }
                if !c.depth {
                    let got: Vec<bool> = p.pixels().iter().map(|p| p.is_some()).collect();
                    assert_eq!(
                        got, expect,
                        "phong perspective: coverage differs from the affine fill"
                    );
                    assert_eq!(
                        got.iter().filter(|b| **b).count() as u32,
                        np,
                        "phong perspective: reported count"
                    );
                }
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some(c) = parse(data) else { return };
    if c.phong {
        phong(&c);
        return;
    }
    for (v, mid) in &c.tris {
        coverage(&c, v, mid);
    }
    match c.format {
        0 => {
            let g = colour::<Rec>(&c, None, Some([i32::MIN; 3]));
            let valid = |x: i32| (0..=255 << 16).contains(&x);
            let in_range = c.tris.iter().all(|(v, mid)| {
                v.iter().all(|p| p.c.iter().all(|x| valid(*x)))
                    && mid.iter().all(|m| m.iter().all(|x| valid(*x)))
            });
            if in_range {
                for p in g.pixels().into_iter().flatten() {
                    assert!(
                        p.iter().all(|ch| (0..=255).contains(ch)),
                        "channel out of range: {p:?}"
                    );
                }
            }
        }
        1 => {
            colour::<Rgb565Le>(&c, 0, 0x5A5A);
        }
        2 => {
            colour::<Rgb888>(&c, [0; 3], [1, 2, 3]);
        }
        _ => {
            colour::<Gray8>(&c, 0, 0x5A);
        }
    }
});
