//! Perspective-correct interpolation of vertex colours (Gouraud shading).
//!
//! Screen-space (affine) interpolation, what every span method does, weights the
//! vertex colours by the screen barycentrics `b_i`. The correct weights are those of
//! the surface point seen through the pixel: `β_i = (b_i/w_i) / Σ_j (b_j/w_j)` with
//! `w` the clip-space w (the eye distance along the view axis). The numerators and
//! the denominator are screen-affine, so they are planes like any attribute; the cost
//! is one reciprocal of the denominator wherever the colour is sampled.
//!
//! Here, per triangle: `q_i = 2¹⁵·w_min/w_i` (Q15, in `[1, 2¹⁵]`), and three planes
//! with 16 extra fraction bits: `E₁ = b₁q₁`, `E₂ = b₂q₂` and `E = Σ b_i q_i`, each
//! Q30 (`≤ 2³⁰`). At a sample pixel `β₁ = E₁/E`, `β₂ = E₂/E` (Q16, through the
//! reciprocal `⌊2⁴⁶/E⌋` taken with the chosen [`Divide`]) and
//! `c = c₀ + β₁(c₁ − c₀) + β₂(c₂ − c₀)`. [`Perspective`] says where to sample:
//! every pixel, or the ends of sub-spans of 2ᵏ pixels with the colour interpolated
//! linearly between them (the last, shorter piece of a span divides its difference
//! by its length through the same [`Divide`]).
//!
//! Depth needs no correction: the depth buffer holds `z/w` of the projection, which
//! *is* affine in screen space; it comes from the usual setup lattice. Coverage is
//! [`super::span::Gradient`]'s.
//!
//! Error: the planes' lattice is within `0.51·8192/2¹⁶ < 0.07` units of Q30 of the
//! exact planes over the 4095-pixel range, the reciprocal within one unit (exact) or
//! the divider's relative bound, and the weights are clamped into `β₁, β₂ ≥ 0`,
//! `β₁ + β₂ ≤ 1`, so a colour always lies in the range of the vertex colours. A
//! triangle whose vertex depths differ by more than 2¹⁵ clamps the far `q` at 1.
//!
//! ```
//! use fixshade::divide::Exact;
//! use fixshade::raster::perspective::{draw_triangle_perspective, Perspective};
//! use fixshade::raster::span::NoDepth;
//! use fixshade::raster::ScreenVertex;
//! use fixshade::shade::Gouraud;
//! use fixshade::target::{Framebuffer, Gray8};
//! let v = |x: i32, y: i32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [g << 16; 3] };
//! // Black near the eye (w = 1) on the left, white far away (w = 4) on the right.
//! let t = [v(0, 0, 0), v(0, 8, 0), v(32, 4, 255)];
//! let mut px = [0u8; 32 * 8];
//! let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 32, 8).unwrap();
//! draw_triangle_perspective::<Gray8, _, NoDepth, Gouraud, Exact>(&mut fb, t, [1, 1, 4], Perspective::PER_PIXEL);
//! // Halfway across the screen is much less than halfway along the surface: the far
//! // half of the surface is squeezed into the right fifth of the screen.
//! let mid = px[4 * 32 + 16];
//! assert!(mid < 60, "{mid}"); // affine interpolation gives about 128
//! ```

use super::setup::{setup_with_det_div, ROUND_BIAS};
use super::span::{pack_pixel, write_run, DepthMode, NoDepth};
use super::{row_range, scan, ScreenVertex};
use crate::divide::{wide_recip, Divide};
use crate::shade::Shading;
use crate::target::{PixelFormat, Target};

/// Where the perspective division is taken: at every pixel, or at the ends of
/// sub-spans of `2^k` pixels (`k` ≤ 6) with linear interpolation between them.
///
/// ```
/// use fixshade::raster::perspective::Perspective;
/// assert_eq!(Perspective::new(16), Some(Perspective::SUB16));
/// assert_eq!(Perspective::PER_PIXEL.span(), 1);
/// assert_eq!(Perspective::new(12), None); // a power of two up to 64
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Perspective {
    log2: u8,
}

impl Perspective {
    /// One division per pixel.
    pub const PER_PIXEL: Perspective = Perspective { log2: 0 };
    /// One division per 8 pixels.
    pub const SUB8: Perspective = Perspective { log2: 3 };
    /// One division per 16 pixels.
    pub const SUB16: Perspective = Perspective { log2: 4 };

    /// Sub-spans of `span` pixels: a power of two from 1 to 64, else `None`.
    pub const fn new(span: u32) -> Option<Perspective> {
        if span.is_power_of_two() && span <= 64 {
            Some(Perspective {
                log2: span.trailing_zeros() as u8,
            })
        } else {
            None
        }
    }

    /// The sub-span length in pixels.
    pub const fn span(self) -> u32 {
        1 << self.log2
    }
}

/// A plane with 16 extra fraction bits on the setup's lattice, kept modulo 2⁶⁴: the
/// true value at a covered pixel is below 2⁴⁶ and so exact.
#[derive(Copy, Clone, Debug)]
struct Plane {
    a: i64,
    gx: i64,
    gy: i64,
}

/// A triangle set up for perspective-correct colours. See the [module docs](self).
#[derive(Copy, Clone, Debug)]
struct PerspSetup {
    /// The usual setup of the positions and depth (colours zero).
    s: super::setup::Setup,
    /// `E₁`, `E₂`, `E`.
    planes: [Plane; 3],
    /// Colour of the top vertex (Q.16 channel units, rounding bias included).
    c0: [i64; 3],
    /// Colour differences middle − top and bottom − top.
    d1: [i64; 3],
    d2: [i64; 3],
}

impl PerspSetup {
    /// `None` for a zero-area triangle. Vertices in the guard band, `w > 0`.
    fn new<D: Divide>(v: [ScreenVertex; 3], w: [i64; 3]) -> Option<PerspSetup> {
        let colourless = v.map(|p| ScreenVertex { c: [0; 3], ..p });
        let (s, det) = setup_with_det_div::<D>(colourless)?;
        // The setup sorted the vertices. A triangle of non-zero area has three
        // distinct positions, so each sorted vertex names its input (colour and w).
        let from = s.v.map(|sv| {
            (0..3)
                .find(|&i| (v[i].x, v[i].y) == (sv.x, sv.y))
                .unwrap_or(0)
        });
        let v = from.map(|i| v[i]);
        let w = from.map(|i| w[i]);
        // q_i = 2^15·w_min/w_i: w shifted below 2^40 first, so `w_min << 15` < 2^55.
        let w = w.map(|x| x.max(1) as u64);
        let top = 64 - (w[0] | w[1] | w[2]).leading_zeros();
        let sh = top.saturating_sub(40);
        let w = w.map(|x| (x >> sh).max(1));
        let w_min = w[0].min(w[1]).min(w[2]);
        let q = w.map(|x| (((w_min << 15) / x).max(1) as i64) << 15); // Q30, ≤ 2^30
        let ox = (16 * s.anchor.0 + 8 - v[0].x) as i128;
        let oy = (16 * s.anchor.1 + 8 - v[0].y) as i128;
        let plane = |at: [i64; 3]| {
            let (gx, gy) = det.gradient(at[1] - at[0], at[2] - at[0], 16);
            // ox, oy < 16; |g| < 2^69 (a numerator below 2^52 over |det| ≥ 1): the
            // sum fits i128; the anchor is kept modulo 2^64 like the increments.
            Plane {
                a: (((at[0] as i128) << 16) + ((ox * gx + oy * gy + 8) >> 4)) as i64,
                gx: gx as i64,
                gy: gy as i64,
            }
        };
        let planes = [
            plane([0, q[1], 0]),
            plane([0, 0, q[2]]),
            plane([q[0], q[1], q[2]]),
        ];
        let c = v.map(|p| p.c.map(|x| x as i64));
        Some(PerspSetup {
            s,
            planes,
            c0: c[0].map(|x| x + ROUND_BIAS as i64),
            d1: core::array::from_fn(|k| c[1][k] - c[0][k]),
            d2: core::array::from_fn(|k| c[2][k] - c[0][k]),
        })
    }

    /// The three plane values at pixel `(x, y)` (wrapping, exact at covered pixels).
    #[inline]
    fn at(&self, x: i32, y: i32) -> [i64; 3] {
        let dx = x.wrapping_sub(self.s.anchor.0) as i64;
        let dy = y.wrapping_sub(self.s.anchor.1) as i64;
        self.planes.map(|p| {
            p.a.wrapping_add(dx.wrapping_mul(p.gx))
                .wrapping_add(dy.wrapping_mul(p.gy))
        })
    }

    /// The planes' change over `n` pixels to the right.
    #[inline]
    fn along(&self, n: i64) -> [i64; 3] {
        self.planes.map(|p| n.wrapping_mul(p.gx))
    }

    /// The perspective-correct colour from plane values: one reciprocal through `D`.
    #[inline]
    fn colour<D: Divide>(&self, e: [i64; 3]) -> [i32; 3] {
        // Q30 values; rounding may leave them a hair outside their true range.
        let den = (e[2] >> 16).max(1) as u64;
        let n1 = ((e[0] >> 16).max(0) as u64).min(den);
        let n2 = ((e[1] >> 16).max(0) as u64).min(den);
        // r ≈ 2^46/den ≤ 2^46, and n ≤ den: n·r ≤ 2^46.
        let r = if D::EXACT {
            (1u64 << 46) / den
        } else {
            wide_recip::<D>(den as u128).scaled(46) as u64
        };
        let b1 = ((n1 * r) >> 30).min(1 << 16) as i64;
        let b2 = (((n2 * r) >> 30) as i64).min((1 << 16) - b1);
        // Colours in range: |d| < 2^25 and β ≤ 2^16, each product below 2^41, and
        // the colour is a convex combination of the vertex colours (plus the bias),
        // so it fits i32. Any i32 colours: |d| < 2^33, the sum below 2^50 fits i64,
        // and the cast wraps (out-of-range input gives wrong colours, never a panic;
        // the differences of two samples below wrap too).
        core::array::from_fn(|k| (self.c0[k] + ((b1 * self.d1[k] + b2 * self.d2[k]) >> 16)) as i32)
    }
}

/// Rasterizes one Gouraud triangle with perspective-correct colours. `w` holds the
/// vertices' clip-space w (any common scale, all positive; triangles with a `w ≤ 0`
/// are not drawn: clip them first). Returns the number of pixels covered. `D`
/// takes the reciprocals ([`crate::divide::Exact`] for the exact result); shadings
/// that do not interpolate ([`crate::shade::Flat`]) draw the last vertex's colour.
///
/// See the [module docs](self) for an example.
pub fn draw_triangle_perspective<P, T, Z, Sh, D>(
    target: &mut T,
    v: [ScreenVertex; 3],
    w: [i64; 3],
    mode: Perspective,
) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
    D: Divide,
{
    if super::outside_guard(v.map(|p| (p.x, p.y))) || w.iter().any(|x| *x <= 0) {
        return 0;
    }
    if !Sh::INTERPOLATE {
        let c = v[2].c;
        let flat = v.map(|p| ScreenVertex { c, ..p });
        return super::draw_triangle::<P, T, super::span::Gradient, Z, Sh>(target, flat);
    }
    let Some(p) = PerspSetup::new::<D>(v, w) else {
        return 0;
    };
    if Z::TEST && !target.has_depth() {
        return fill::<P, T, NoDepth, Sh, D>(target, &p, mode);
    }
    fill::<P, T, Z, Sh, D>(target, &p, mode)
}

fn fill<P, T, Z, Sh, D>(target: &mut T, p: &PerspSetup, mode: Perspective) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
    D: Divide,
{
    let Some(rows) = row_range(&p.s, target.rows()) else {
        return 0;
    };
    let gz = p.s.gx[3];
    let log2 = mode.log2 as u32;
    let sub = 1usize << log2;
    // Per-triangle steps: one pixel, and one sub-span, of the planes and the depth.
    let (g1, gsub) = (p.along(1), p.along(sub as i64));
    let zsub = (sub as i32).wrapping_mul(gz);
    let add = |e: [i64; 3], g: &[i64; 3]| -> [i64; 3] {
        core::array::from_fn(|k| e[k].wrapping_add(g[k]))
    };
    scan::<P, T, Z, _>(target, &p.s, rows, false, |color, depth, span| {
        let n = color.len();
        let mut e = p.at(span.x0, span.y);
        let mut z = span.v[3];
        if sub == 1 {
            for i in 0..n {
                let c = p.colour::<D>(e);
                let mut none = 0u16;
                let d = if Z::TEST { &mut depth[i] } else { &mut none };
                pack_pixel::<P, Z>(&mut color[i], d, &[c[0], c[1], c[2], z]);
                e = add(e, &g1);
                z = z.wrapping_add(gz);
            }
            return;
        }
        let mut c = p.colour::<D>(e);
        let mut i = 0;
        // Whole sub-spans: each one's end is the next one's start.
        while i + sub < n {
            e = add(e, &gsub);
            let next = p.colour::<D>(e);
            let inc = core::array::from_fn(|k| next[k].wrapping_sub(c[k]) >> log2);
            run::<P, Z, Sh>(color, depth, i, (sub, inc), c, z, gz);
            c = next;
            i += sub;
            z = z.wrapping_add(zsub);
        }
        // The rest of the span (1..=sub pixels), interpolated to its last pixel.
        let last = (n - 1 - i) as u32;
        let inc = if last == 0 {
            [0; 3]
        } else {
            let end = p.colour::<D>(add(e, &p.along(last as i64)));
            let r = D::recip(last);
            core::array::from_fn(|k| D::div(end[k].wrapping_sub(c[k]), &r))
        };
        run::<P, Z, Sh>(color, depth, i, (n - i, inc), c, z, gz);
    })
}

/// Writes `len` pixels from `i` on: colour `c` stepping by `inc`, depth `z` by `gz`.
#[inline(always)]
fn run<P: PixelFormat, Z: DepthMode, Sh: Shading>(
    color: &mut [P::Raw],
    depth: &mut [u16],
    i: usize,
    (len, inc): (usize, [i32; 3]),
    c: [i32; 3],
    z: i32,
    gz: i32,
) {
    let d: &mut [u16] = if Z::TEST {
        &mut depth[i..i + len]
    } else {
        &mut []
    };
    write_run::<P, Z, Sh>(
        &mut color[i..i + len],
        d,
        [c[0], c[1], c[2], z],
        &[inc[0], inc[1], inc[2], gz],
    );
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::divide::{Exact, ShiftAdd};
    use crate::raster::span::{Gradient, NoDepth};
    use crate::raster::GUARD;
    use crate::shade::Gouraud;
    use crate::target::{Framebuffer, Gray8};
    use std::vec;
    use std::vec::Vec;

    fn v(x: i32, y: i32, g: i32) -> ScreenVertex {
        ScreenVertex {
            x: x * 16 + 3,
            y: y * 16 + 5,
            z: 0,
            c: [g << 16; 3],
        }
    }

    fn draw(t: [ScreenVertex; 3], w: [i64; 3], m: Perspective) -> Vec<u8> {
        let mut px = vec![0u8; 64 * 64];
        let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 64, 64).unwrap();
        draw_triangle_perspective::<Gray8, _, NoDepth, Gouraud, Exact>(&mut fb, t, w, m);
        px
    }

    /// Equal w is affine interpolation: within one step of the gradient span
    /// method, with the same coverage.
    #[test]
    fn equal_w_is_affine() {
        let t = [v(3, 2, 10), v(60, 20, 250), v(9, 61, 120)];
        let mut px = vec![0u8; 64 * 64];
        let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 64, 64).unwrap();
        crate::raster::draw_triangle::<Gray8, _, Gradient, NoDepth, Gouraud>(&mut fb, t);
        for m in [
            Perspective::PER_PIXEL,
            Perspective::SUB8,
            Perspective::SUB16,
        ] {
            let p = draw(t, [7, 7, 7], m);
            for (a, b) in p.iter().zip(&px) {
                assert_eq!(*a == 0, *b == 0);
                assert!((*a as i32 - *b as i32).abs() <= 1, "{a} {b}");
            }
        }
    }

    /// Against the exact perspective-correct colour at every covered pixel centre;
    /// sub-spans against the chord between the exact colours at their ends.
    #[test]
    fn matches_the_exact_weights() {
        let t = [v(3, 2, 10), v(60, 20, 250), v(9, 61, 120)];
        let w = [1000i64, 9000, 3000];
        let pix = draw(t, w, Perspective::PER_PIXEL);
        let f = |p: &ScreenVertex| (p.x as f64 / 16.0, p.y as f64 / 16.0);
        let (a, b, c) = (f(&t[0]), f(&t[1]), f(&t[2]));
        let area = (b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1);
        let exact = |x: i32, y: usize| {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let l1 = ((px - a.0) * (c.1 - a.1) - (c.0 - a.0) * (py - a.1)) / area;
            let l2 = ((b.0 - a.0) * (py - a.1) - (px - a.0) * (b.1 - a.1)) / area;
            let q = [
                (1.0 - l1 - l2) / w[0] as f64,
                l1 / w[1] as f64,
                l2 / w[2] as f64,
            ];
            (10.0 * q[0] + 250.0 * q[1] + 120.0 * q[2]) / (q[0] + q[1] + q[2])
        };
        let mut covered = 0;
        for y in 0..64 {
            for x in 0..64 {
                let got = pix[y * 64 + x];
                if got != 0 {
                    covered += 1;
                    // Rounding (0.5) plus the weights' floors: two units of 2⁻¹⁶
                    // each over a colour range of 240, below 0.02.
                    let e = exact(x as i32, y);
                    assert!((got as f64 - e).abs() <= 0.52, "({x},{y}) {got} {e}");
                }
            }
        }
        assert!(covered > 1000);
        let mut worst_chord = 0.0f64;
        for m in [Perspective::SUB8, Perspective::SUB16] {
            let sub = draw(t, w, m);
            let l = m.span() as i32;
            for y in 0..64 {
                let row = &sub[y * 64..(y + 1) * 64];
                let Some(x0) = row.iter().position(|p| *p != 0) else {
                    continue;
                };
                let x1 = row.iter().rposition(|p| *p != 0).unwrap() + 1;
                let (x0, x1) = (x0 as i32, x1 as i32);
                for x in x0..x1 {
                    let s = x0 + (x - x0) / l * l;
                    let e = if s + l < x1 { s + l } else { x1 - 1 };
                    let chord = if e == s {
                        exact(s, y)
                    } else {
                        exact(s, y) + (exact(e, y) - exact(s, y)) * (x - s) as f64 / (e - s) as f64
                    };
                    worst_chord = worst_chord.max((chord - exact(x, y)).abs());
                    let got = row[x as usize] as f64;
                    // The ends' 0.52, the increments' floors (one unit of 2⁻¹⁶ a step).
                    assert!((got - chord).abs() <= 1.05, "({x},{y}) {got} {chord}");
                }
            }
        }
        // The triangle is steep in depth (w from 1000 to 9000 over 60 pixels): the
        // chords stray far from the curve, which is what sub-spans cost.
        assert!(worst_chord > 5.0, "{worst_chord}");
    }

    /// An approximate divider moves colours, never coverage, and stays in range.
    #[test]
    fn dividers_keep_coverage() {
        let t = [v(3, 2, 5), v(60, 20, 255), v(9, 61, 250)];
        let w = [100i64, 90000, 3000];
        let exact = draw(t, w, Perspective::SUB8);
        let mut px = vec![0u8; 64 * 64];
        let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 64, 64).unwrap();
        draw_triangle_perspective::<Gray8, _, NoDepth, Gouraud, ShiftAdd<4>>(
            &mut fb,
            t,
            w,
            Perspective::SUB8,
        );
        for (a, b) in px.iter().zip(&exact) {
            assert_eq!(*a == 0, *b == 0);
        }
    }

    /// Random triangles over the whole guard band, slivers and extreme depth ratios
    /// included: no panic (overflow checks are on in tests), and the same covered
    /// pixel count as the gradient span method.
    #[test]
    fn random_triangles_cover_what_gradient_covers() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let lim = (GUARD - 1) as u64;
        for i in 0..3000 {
            // Half the triangles near the target, half anywhere in the guard band.
            let coord = |r: u64| {
                if i % 2 == 0 {
                    (r % (80 * 16)) as i32 - 8 * 16
                } else {
                    (r % (2 * lim + 1)) as i32 - lim as i32
                }
            };
            let t: [ScreenVertex; 3] = core::array::from_fn(|_| ScreenVertex {
                x: coord(next()),
                y: coord(next()),
                z: (next() as u32) >> 1,
                // In range for most; any i32 for every fifth (found by the fuzzer:
                // a difference of two out-of-range samples overflowed).
                c: if i % 5 == 4 {
                    [next() as i32, next() as i32, next() as i32]
                } else {
                    [(next() % (256 << 16)) as i32; 3]
                },
            });
            let w: [i64; 3] = core::array::from_fn(|_| 1 + (next() % (1 << (next() % 41))) as i64);
            let mut a = vec![0u8; 64 * 64];
            let mut b = vec![0u8; 64 * 64];
            let mut fa = Framebuffer::<Gray8>::new(&mut a, None, 64, 64).unwrap();
            let mut fb = Framebuffer::<Gray8>::new(&mut b, None, 64, 64).unwrap();
            let n =
                crate::raster::draw_triangle::<Gray8, _, Gradient, NoDepth, Gouraud>(&mut fa, t);
            for m in [Perspective::PER_PIXEL, Perspective::SUB16] {
                let k = draw_triangle_perspective::<Gray8, _, NoDepth, Gouraud, Exact>(
                    &mut fb, t, w, m,
                );
                assert_eq!(n, k, "{t:?} {w:?}");
                let k = draw_triangle_perspective::<Gray8, _, NoDepth, Gouraud, ShiftAdd<4>>(
                    &mut fb, t, w, m,
                );
                assert_eq!(n, k, "{t:?} {w:?}");
            }
        }
    }
}
