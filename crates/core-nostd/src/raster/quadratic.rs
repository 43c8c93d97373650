//! The quadratic intensity surface (seed 003, DESIGN.md method 5).
//!
//! Per triangle, each colour channel is the quadratic Lagrange interpolant through
//! the three vertex colours and the three edge-midpoint colours (lit at the
//! midpoints by the caller):
//!
//! ```text
//! I = I0·u(2u−1) + I1·v(2v−1) + I2·w(2w−1) + 4·I01·uv + 4·I12·vw + 4·I20·wu
//! ```
//!
//! with barycentrics `u, v, w` (affine in screen x, y). The fit is done in the
//! normalised triangle frame: with `u = 1 − v − w`,
//! `I = I0 + p1·v + p2·w + q11·v² + q22·w² + q12·vw`, whose weights are integer
//! combinations of the six samples (no 6×6 solve, nothing to be ill-conditioned).
//! The barycentrics are exact integer linear forms over the determinant,
//! `v = L1(i, j)/det`, `w = L2(i, j)/det`, in the pixel offsets `i = x − xa`,
//! `j = y − ya` from the anchor pixel. Expanding gives the screen-space polynomial of
//! the seed,
//!
//! ```text
//! I(i, j) = A·i² + B·j² + C·ij + D·i + E·j + F,
//! ```
//!
//! whose coefficients are exact rationals `n/det²` and `n/det`, each rounded once to
//! [`FRAC`] = 40 fraction bits of a channel unit (multiplying by one reciprocal of
//! `det` and one of `det²` per triangle; within ½ + 2⁻²⁹ unit of the exact
//! rounding).
//!
//! Bounds and error: samples are below 2²⁴ (Q.16 channel units, MAX ≤ 255); the
//! weights `p`, `q` below 2²⁷; the linear forms' coefficients below 2²² (guard band
//! |dx|, |dy| < 2¹⁷, and the anchor is within one pixel of vertex 0); so every
//! numerator shifted left by 24 is below 2⁹⁷ and fits `i128`. A coefficient is within
//! ½ unit (D, E, F, made of two rounded parts: 1 unit; plus 2⁻²⁹ from the
//! reciprocals) of the exact one, so at a
//! pixel with |i|, |j| < 2¹³ (anchor and pixel both within ±4096 of the origin) the
//! polynomial is off by at most ½(i² + j² + |ij|) + |i| + |j| + 1 < 2²⁷ units of
//! 2⁻⁴⁰ channel units, i.e. below 2⁻¹³ of an output step (the requirement is 2⁻⁴).
//!
//! Evaluation is wrapping `i64` arithmetic, exact modulo 2⁶⁴ (like the `i32`
//! lattice of [`super::setup`]): the coefficients themselves may exceed `i64` on a
//! sliver (they are kept modulo 2⁶⁴), but the value at a covered pixel is the
//! interpolant inside the closed triangle, bounded by the Lebesgue constant 5/3 of
//! quadratic Lagrange interpolation times the largest sample, below 2⁴⁹ in Q.40, so
//! it fits and the wrapped result is exact there. No sliver needs a fallback; the
//! renderer falls back to Gouraud only for triangles that go through the clipper.
//!
//! Filling uses forward differences, so the span loop has no multiplication:
//! along a row `P_x = I(x+1) − I(x) = 2A·i + A + C·j + D` grows by `2A` per pixel.
//! The 2×2 block scheme of seed 003 fills two scanlines at once with four units at
//! `(x, y)`, `(x+1, y)`, `(x, y+1)`, `(x+1, y+1)` (the +1x, +1y, +1x+1y moves, seed
//! eqs. 5–7), each stepping two columns by `I(x+2) − I(x)`, which grows by `8A`; the
//! walk then steps +2 rows. Both orders are integer arithmetic on the same integer
//! polynomial, so they give bit-identical values (tested). A quadratic overshoots
//! between its samples, so the colour is clamped to [0, MAX] per channel at the
//! pixel. Depth stays on the linear lattice of [`Setup`], coverage is the edge
//! walker's (the top-left rule), identical to [`super::span::Gradient`].

use crate::arrays;
use core::ops::Range;

use super::edge::{first_row, EdgeStepper};
use super::pixel::DepthMode;
use super::setup::{setup_div, Setup};
pub use super::shading::Fill;
use super::vertex::ScreenVertex;
use crate::divide::{wide_recip, Divide, Exact};
use crate::target::{DepthFormat, PixelFormat, Target};

/// Fraction bits of the surface values, in channel units.
pub const FRAC: u32 = 40;

/// The fitted surface of one triangle.
///
/// ```
/// use fixshade::raster::quadratic::Quad;
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [g << 16, 0, 0] };
/// // Vertices dark, edge midpoints bright: a surface that bulges in the middle.
/// let q = Quad::fit([v(0, 0, 0), v(0, 32, 0), v(32, 0, 0)], [[100 << 16, 0, 0]; 3]).unwrap();
/// assert!(q.coef[0][0] < 0); // A (the x² term) is negative: a dome
/// assert!(Quad::fit([v(0, 0, 0), v(8, 8, 0), v(16, 16, 0)], [[0; 3]; 3]).is_none());
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Quad {
    /// Anchor pixel: `i = x − anchor.0`, `j = y − anchor.1`.
    pub anchor: (i32, i32),
    /// Per channel `[A, B, C, D, E, F]` in Q.40 channel units (modulo 2⁶⁴), the
    /// rounding bias ½ included in F.
    pub coef: [[i64; 6]; 3],
}

/// A divisor `d ≠ 0` as its reciprocal `⌊2¹²⁷ / |d|⌋` and sign: one division per
/// triangle instead of one per coefficient.
#[derive(Copy, Clone)]
struct Recip {
    inv: u128,
    neg: bool,
}

impl Recip {
    /// Through `D`: [`Exact`] gives `⌊2¹²⁷ / |d|⌋`; any other variant
    /// [`wide_recip`]'s under-estimate, within its relative error `η`. Either is at
    /// most `2¹²⁷/|d|`, so [`Recip::div`]'s overflow bounds hold; its rounding claim
    /// is the exact reciprocal's (an approximate one adds `η` relative).
    fn new<D: Divide>(d: i128) -> Recip {
        let inv = if D::is_exact() {
            (1u128 << 127) / d.unsigned_abs()
        } else {
            // r ≤ 2^30 scaled to 2^127: below 2^127, and at least 1.
            wide_recip::<D>(d.unsigned_abs()).scaled(127)
        };
        Recip { inv, neg: d < 0 }
    }

    /// `n / d` rounded to nearest, for |n| < 2⁹⁸. With `inv = 2¹²⁷/|d| − ε`
    /// (0 ≤ ε < 1), `|n|·inv / 2¹²⁷` is below the exact quotient by less than
    /// `|n| / 2¹²⁷ < 2⁻²⁹`, so the result is the rounded quotient, or one off only
    /// when that is within 2⁻²⁹ of a half: an error below ½ + 2⁻²⁹ units. The
    /// product `|n|·inv` < 2²²⁵ is formed from four 64×64-bit products.
    #[inline]
    fn div(&self, n: i128) -> i128 {
        let a = n.unsigned_abs();
        let b = self.inv;
        let (a0, a1) = (a as u64 as u128, a >> 64);
        let (b0, b1) = (b as u64 as u128, b >> 64);
        let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
        // Bits 64..128 of the product plus the rounding half 2^126, and the carry.
        let mid = (p00 >> 64) + (p01 as u64 as u128) + (p10 as u64 as u128) + (1 << 62);
        let high = p11 + (p01 >> 64) + (p10 >> 64) + (mid >> 64);
        let q = ((high << 1) | ((mid as u64) >> 63) as u128) as i128;
        if (n < 0) != self.neg {
            -q
        } else {
            q
        }
    }
}

impl Quad {
    /// Fits the surface through the vertex colours `v[k].c` and the midpoint colours
    /// `mid[k]` of the edges `v[k] → v[(k + 1) % 3]` (Q.16 channel units, 0..=MAX).
    /// `None` for a zero-area triangle.
    pub fn fit(v: [ScreenVertex; 3], mid: [[i32; 3]; 3]) -> Option<Quad> {
        Self::fit_div::<Exact>(v, mid)
    }

    /// [`Quad::fit`] with its two reciprocals (of `det` and `det²`) taken through
    /// the divider `D` ([`Quad::fit`] is `fit_div::<Exact>`). An approximate `D`
    /// never over-estimates: the parts of the coefficients over `det` shrink by at
    /// most `D`'s relative error `η` ([`wide_recip`]), those over `det²` by at most
    /// `η` of their own, so a pixel's value is off by at most `η` times the sum of
    /// the magnitudes of its terms (the pixel clamps the colour to the channel
    /// range, as for the exact fit's overshoot).
    ///
    /// ```
    /// use fixshade::divide::{Exact, Table};
    /// use fixshade::raster::quadratic::Quad;
    /// use fixshade::raster::ScreenVertex;
    /// let v = |x: i32, y: i32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [g << 16, 0, 0] };
    /// let (t, m) = ([v(0, 0, 0), v(3, 40, 90), v(37, 5, 200)], [[160 << 16, 0, 0]; 3]);
    /// assert_eq!(Quad::fit_div::<Exact>(t, m), Quad::fit(t, m));
    /// // The 12-bit table: every surface value within 0.2 of a step of the exact one.
    /// let (e, a) = (Quad::fit(t, m).unwrap(), Quad::fit_div::<Table>(t, m).unwrap());
    /// for (x, y) in [(1, 1), (2, 30), (30, 4), (10, 10)] {
    ///     assert!((e.at(x, y)[0] - a.at(x, y)[0]).abs() < (1 << 40) / 5);
    /// }
    /// ```
    pub fn fit_div<D: Divide>(v: [ScreenVertex; 3], mid: [[i32; 3]; 3]) -> Option<Quad> {
        // Rotate (keeping the edge ↔ midpoint pairing) so vertex 0 is the top one,
        // the vertex the anchor pixel is taken from.
        let top = (0..3).min_by_key(|&k| (v[k].y, v[k].x)).unwrap_or(0);
        let vv: [ScreenVertex; 3] = arrays::from_fn(|k| v[(k + top) % 3]);
        let mm: [[i32; 3]; 3] = arrays::from_fn(|k| mid[(k + top) % 3]);
        let [p0, p1, p2] = vv;
        let (dx1, dy1) = ((p1.x - p0.x) as i64, (p1.y - p0.y) as i64);
        let (dx2, dy2) = ((p2.x - p0.x) as i64, (p2.y - p0.y) as i64);
        let det = dx1 * dy2 - dx2 * dy1;
        if det == 0 {
            return None;
        }
        let anchor = (first_row(p0.x), first_row(p0.y));
        // Anchor centre relative to vertex 0, in [0, 16) subpixels.
        let ox = (16 * anchor.0 + 8 - p0.x) as i64;
        let oy = (16 * anchor.1 + 8 - p0.y) as i64;
        // det·v = a1·i + b1·j + c1, det·w = a2·i + b2·j + c2 (all below 2^22).
        let (a1, b1, c1) = (16 * dy2, -16 * dx2, ox * dy2 - oy * dx2);
        let (a2, b2, c2) = (-16 * dy1, 16 * dx1, oy * dx1 - ox * dy1);
        let det1 = det as i128;
        let r1 = Recip::new::<D>(det1);
        let r2 = Recip::new::<D>(det1 * det1); // det² < 2^70
                                               // Channel-independent products (each below 2^46, so i64), per monomial
                                               // i², j², ij, i, j, 1: the factors of q11, q22, q12 (over det²) and, for
                                               // the linear monomials, of p1, p2 (over det).
        let m2: [[i64; 3]; 6] = [
            [a1 * a1, a2 * a2, a1 * a2],
            [b1 * b1, b2 * b2, b1 * b2],
            [2 * a1 * b1, 2 * a2 * b2, a1 * b2 + a2 * b1],
            [2 * a1 * c1, 2 * a2 * c2, a1 * c2 + a2 * c1],
            [2 * b1 * c1, 2 * b2 * c2, b1 * c2 + b2 * c1],
            [c1 * c1, c2 * c2, c1 * c2],
        ];
        let m1: [[i64; 2]; 3] = [[a1, a2], [b1, b2], [c1, c2]];
        // i64 × i64 → i128: one widening multiply.
        let w = |x: i64, y: i64| x as i128 * y as i128;
        let mut coef = [[0i64; 6]; 3];
        for (ch, out) in coef.iter_mut().enumerate() {
            if vv.iter().all(|p| p.c[ch] == 0) && mm.iter().all(|m| m[ch] == 0) {
                // A black channel (and channels 1, 2 of grey formats).
                out[5] = 1 << (FRAC - 1);
                continue;
            }
            let i0 = p0.c[ch] as i64;
            let i1 = p1.c[ch] as i64;
            let i2 = p2.c[ch] as i64;
            let (i01, i12, i20) = (mm[0][ch] as i64, mm[1][ch] as i64, mm[2][ch] as i64);
            let p1w = -3 * i0 - i1 + 4 * i01;
            let p2w = -3 * i0 - i2 + 4 * i20;
            let q11 = 2 * i0 + 2 * i1 - 4 * i01;
            let q22 = 2 * i0 + 2 * i2 - 4 * i20;
            let q12 = 4 * (i0 + i12 - i01 - i20);
            // Numerators over det² (quadratic part) and det (linear part).
            let n2 = |m: &[i64; 3]| w(q11, m[0]) + w(q22, m[1]) + w(q12, m[2]);
            let n1 = |m: &[i64; 2]| w(p1w, m[0]) + w(p2w, m[1]);
            let (na, nb, nc) = (n2(&m2[0]), n2(&m2[1]), n2(&m2[2]));
            let (nd2, ne2, nf2) = (n2(&m2[3]), n2(&m2[4]), n2(&m2[5]));
            let (nd1, ne1, nf1) = (n1(&m1[0]), n1(&m1[1]), n1(&m1[2]));
            let i0 = i0 as i128;
            const S: u32 = FRAC - 16; // Q.16 samples to Q.40
            let q = |n: i128| r2.div(n << S);
            let l = |n: i128| r1.div(n << S);
            let f = (i0 << S) + (1 << (FRAC - 1)) + l(nf1) + q(nf2);
            // Modulo 2^64 by design (see the module comment).
            *out = [
                q(na) as i64,
                q(nb) as i64,
                q(nc) as i64,
                (l(nd1) + q(nd2)) as i64,
                (l(ne1) + q(ne2)) as i64,
                f as i64,
            ];
        }
        Some(Quad { anchor, coef })
    }

    /// The surface values at pixel `(x, y)`, Q.40 channel units with the rounding
    /// bias (wrapping: exact at covered pixels).
    #[inline]
    pub fn at(&self, x: i32, y: i32) -> [i64; 3] {
        let i = x.wrapping_sub(self.anchor.0) as i64;
        let j = y.wrapping_sub(self.anchor.1) as i64;
        arrays::map(self.coef, |[a, b, c, d, e, f]| {
            a.wrapping_mul(i.wrapping_mul(i))
                .wrapping_add(b.wrapping_mul(j.wrapping_mul(j)))
                .wrapping_add(c.wrapping_mul(i.wrapping_mul(j)))
                .wrapping_add(d.wrapping_mul(i))
                .wrapping_add(e.wrapping_mul(j))
                .wrapping_add(f)
        })
    }

    /// `I(x+1, y) − I(x, y)` per channel: `2A·i + A + C·j + D`.
    #[inline]
    fn dx(&self, x: i32, y: i32) -> [i64; 3] {
        let i = x.wrapping_sub(self.anchor.0) as i64;
        let j = y.wrapping_sub(self.anchor.1) as i64;
        arrays::map(self.coef, |[a, _, c, d, _, _]| {
            a.wrapping_mul(2 * i + 1)
                .wrapping_add(c.wrapping_mul(j))
                .wrapping_add(d)
        })
    }

    /// `I(x, y+1) − I(x, y)` per channel: `2B·j + B + C·i + E`.
    #[inline]
    fn dy(&self, x: i32, y: i32) -> [i64; 3] {
        let i = x.wrapping_sub(self.anchor.0) as i64;
        let j = y.wrapping_sub(self.anchor.1) as i64;
        arrays::map(self.coef, |[_, b, c, _, e, _]| {
            b.wrapping_mul(2 * j + 1)
                .wrapping_add(c.wrapping_mul(i))
                .wrapping_add(e)
        })
    }
}

/// The channel integer of a surface value: rounded (bias in F), clamped to 0..=max.
#[inline(always)]
fn chan(v: i64, max: u32) -> u32 {
    (v >> FRAC).clamp(0, max as i64) as u32
}

#[inline(always)]
fn pack<P: PixelFormat>(v: &[i64; 3]) -> P::Raw {
    if P::GRAY {
        P::pack(chan(v[0], P::MAX[0]), 0, 0)
    } else {
        P::pack(
            chan(v[0], P::MAX[0]),
            chan(v[1], P::MAX[1]),
            chan(v[2], P::MAX[2]),
        )
    }
}

#[inline(always)]
fn add3(a: &mut [i64; 3], b: &[i64; 3]) {
    for k in 0..3 {
        a[k] = a[k].wrapping_add(b[k]);
    }
}

/// Walks the rows of a set-up triangle within `rows`, calling `f(y, x0, x1)` for
/// every row from the first to the last (the span `[x0, x1)` clipped to
/// `[0, width)`, possibly empty). Coverage is exactly that of
/// [`super::draw_setup`].
fn walk_rows(s: &Setup, rows: Range<i32>, width: i32, mut f: impl FnMut(i32, i32, i32)) {
    let [t, m, b] = s.v;
    let y_top = first_row(t.y).max(rows.start);
    let y_mid = first_row(m.y);
    let y_bot = first_row(b.y).min(rows.end);
    if y_top >= y_bot {
        return;
    }
    let mut long = EdgeStepper::new((t.x, t.y), (b.x, b.y), y_top);
    for (p, q, ys, ye) in [
        (&t, &m, y_top, y_mid.min(y_bot)),
        (&m, &b, y_mid.max(y_top), y_bot),
    ] {
        if ys >= ye {
            continue;
        }
        let mut es = EdgeStepper::new((p.x, p.y), (q.x, q.y), ys);
        for y in ys..ye {
            let (l, r) = if s.mid_left {
                (es.q, long.q)
            } else {
                (long.q, es.q)
            };
            f(y, l.max(0), r.min(width));
            es.step();
            long.step();
        }
    }
}

/// Stores `p` at `c` if the lattice depth `z` passes the test.
#[inline(always)]
fn put<P: PixelFormat, Z: DepthMode>(
    c: &mut P::Raw,
    d: Option<&mut impl DepthFormat>,
    z: i32,
    p: P::Raw,
) {
    if Z::TEST {
        if let Some(d) = d {
            if !d.write_if_nearer(z) {
                return;
            }
        }
    }
    P::store(c, p);
}

/// Fills `[x0, x1)` of row `y` with forward differences along the row.
fn fill_row<P: PixelFormat, T: Target<P>, Z: DepthMode>(
    target: &mut T,
    s: &Setup,
    q: &Quad,
    y: i32,
    x0: i32,
    x1: i32,
) {
    let mut v = q.at(x0, y);
    let mut px = q.dx(x0, y);
    let a2: [i64; 3] = arrays::map(q.coef, |c| c[0].wrapping_mul(2));
    let mut z = s.at(x0, y)[3];
    let gz = s.gx[3];
    let (crow, drow) = target.row(y);
    let (a, b) = (x0 as usize, x1 as usize);
    if Z::TEST {
        for (c, d) in crow[a..b].iter_mut().zip(drow[a..b].iter_mut()) {
            put::<P, Z>(c, Some(d), z, pack::<P>(&v));
            add3(&mut v, &px);
            add3(&mut px, &a2);
            z = z.wrapping_add(gz);
        }
    } else {
        for c in crow[a..b].iter_mut() {
            P::store(c, pack::<P>(&v));
            add3(&mut v, &px);
            add3(&mut px, &a2);
        }
    }
}

/// Columns per chunk of the 2×2 block fill: the four units fill a chunk of two
/// rows into a small stack buffer, then each row is stored (a target lends one row
/// at a time).
const CHUNK: usize = 32;

/// Fills rows `y` (`[a0, a1)`) and `y + 1` (`[b0, b1)`), both non-empty, in 2×2
/// blocks.
#[allow(clippy::too_many_arguments)]
fn fill_pair<P: PixelFormat, T: Target<P>, Z: DepthMode>(
    target: &mut T,
    s: &Setup,
    q: &Quad,
    y: i32,
    (a0, a1): (i32, i32),
    (b0, b1): (i32, i32),
) {
    let xs = a0.min(b0);
    let xe = a1.max(b1);
    // The four units at (x, y), (x+1, y), (x, y+1), (x+1, y+1) (seed eqs. 1, 5, 6, 7).
    let v00 = q.at(xs, y);
    let px = q.dx(xs, y);
    let py = q.dy(xs, y);
    let mut v10 = v00;
    add3(&mut v10, &px);
    let mut v01 = v00;
    add3(&mut v01, &py);
    let mut v11 = v10;
    add3(&mut v11, &q.dy(xs + 1, y));
    let mut u = [v00, v10, v01, v11];
    // Two-column steps I(x+2) − I(x) = 4A·i + 4A + 2C·j + 2D for the unit at (x, y);
    // +4A for the x+1 units, +2C for the y+1 units; all grow by 8A per step.
    let i = xs.wrapping_sub(q.anchor.0) as i64;
    let j = y.wrapping_sub(q.anchor.1) as i64;
    let s00: [i64; 3] = arrays::map(q.coef, |[a, _, c, d, _, _]| {
        a.wrapping_mul(4 * i + 4)
            .wrapping_add(c.wrapping_mul(2 * j))
            .wrapping_add(d.wrapping_mul(2))
    });
    let a4 = arrays::map(q.coef, |c| c[0].wrapping_mul(4));
    let c2 = arrays::map(q.coef, |c| c[2].wrapping_mul(2));
    let a8 = arrays::map(q.coef, |c| c[0].wrapping_mul(8));
    let mut s10 = s00;
    add3(&mut s10, &a4);
    let mut s01 = s00;
    add3(&mut s01, &c2);
    let mut s11 = s10;
    add3(&mut s11, &c2);
    let mut st = [s00, s10, s01, s11];
    let gz = s.gx[3];
    let mut x = xs;
    let mut top = [P::Raw::default(); CHUNK];
    let mut bot = [P::Raw::default(); CHUNK];
    while x < xe {
        let n = ((xe - x) as usize).min(CHUNK);
        let mut k = 0;
        while k < n {
            top[k] = pack::<P>(&u[0]);
            bot[k] = pack::<P>(&u[2]);
            if k + 1 < n {
                top[k + 1] = pack::<P>(&u[1]);
                bot[k + 1] = pack::<P>(&u[3]);
            }
            for (uu, ss) in u.iter_mut().zip(st.iter_mut()) {
                add3(uu, ss);
                add3(ss, &a8);
            }
            k += 2;
        }
        let ce = x + n as i32;
        for (row, (r0, r1), buf) in [(y, (a0, a1), &top), (y + 1, (b0, b1), &bot)] {
            let (lo, hi) = (r0.max(x), r1.min(ce));
            if lo >= hi {
                continue;
            }
            let (crow, drow) = target.row(row);
            let cs = &mut crow[lo as usize..hi as usize];
            let src = &buf[(lo - x) as usize..(hi - x) as usize];
            if Z::TEST {
                let mut z = s.at(lo, row)[3];
                let ds = &mut drow[lo as usize..hi as usize];
                for ((c, d), p) in cs.iter_mut().zip(ds.iter_mut()).zip(src) {
                    put::<P, Z>(c, Some(d), z, *p);
                    z = z.wrapping_add(gz);
                }
            } else {
                for (c, p) in cs.iter_mut().zip(src) {
                    P::store(c, *p);
                }
            }
        }
        x = ce;
    }
}

/// Rasterizes a set-up triangle with the surface `q`. Returns the number of pixels
/// covered inside the target (before the depth test).
///
/// ```
/// use fixshade::raster::quadratic::{draw_setup_quad, Fill, Quad};
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::ScreenVertex;
/// use fixshade::target::{Framebuffer, Gray8};
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [50 << 16; 3] };
/// let t = [v(0, 0), v(0, 16), v(16, 0)];
/// // Midpoints equal to the vertices: the surface is flat, grey 50 everywhere.
/// let (s, q) = (setup(t).unwrap(), Quad::fit(t, [[50 << 16; 3]; 3]).unwrap());
/// let mut px = [0u8; 16 * 16];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 16, 16).unwrap();
/// let n = draw_setup_quad::<Gray8, _, NoDepth>(&mut fb, &s, &q, Fill::Blocks);
/// assert_eq!(px.iter().filter(|&&p| p == 50).count(), n as usize);
/// ```
pub fn draw_setup_quad<P: PixelFormat, T: Target<P>, Z: DepthMode>(
    target: &mut T,
    s: &Setup,
    q: &Quad,
    fill: Fill,
) -> u32 {
    if Z::TEST && !target.has_depth() {
        return draw_setup_quad::<P, T, super::span::NoDepth>(target, s, q, fill);
    }
    let width = target.width() as i32;
    let rows = target.rows();
    let mut covered = 0u32;
    match fill {
        Fill::Rows => walk_rows(s, rows, width, |y, x0, x1| {
            if x0 < x1 {
                covered += (x1 - x0) as u32;
                fill_row::<P, T, Z>(target, s, q, y, x0, x1);
            }
        }),
        Fill::Blocks => {
            let mut pending: Option<(i32, i32, i32)> = None;
            walk_rows(s, rows, width, |y, x0, x1| {
                if x0 < x1 {
                    covered += (x1 - x0) as u32;
                }
                match pending.take() {
                    None => pending = Some((y, x0, x1)),
                    Some((py, p0, p1)) => match (p0 < p1, x0 < x1) {
                        (true, true) => fill_pair::<P, T, Z>(target, s, q, py, (p0, p1), (x0, x1)),
                        (true, false) => fill_row::<P, T, Z>(target, s, q, py, p0, p1),
                        (false, true) => fill_row::<P, T, Z>(target, s, q, y, x0, x1),
                        (false, false) => {}
                    },
                }
            });
            if let Some((py, p0, p1)) = pending {
                if p0 < p1 {
                    fill_row::<P, T, Z>(target, s, q, py, p0, p1);
                }
            }
        }
    }
    covered
}

/// Rasterizes one triangle with the quadratic surface through its vertex colours
/// and the edge-midpoint colours `mid[k]` (edge `v[k] → v[(k + 1) % 3]`). Vertices
/// outside the guard band or a zero area draw nothing.
///
/// ```
/// use fixshade::raster::quadratic::{draw_quadratic, Fill};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::ScreenVertex;
/// use fixshade::target::{Framebuffer, Gray8};
/// let mut px = [0u8; 16 * 16];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 16, 16).unwrap();
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [0; 3] };
/// // Black corners, white edge midpoints: the inside is lit although no vertex is.
/// draw_quadratic::<Gray8, _, NoDepth>(&mut fb, [v(0, 0), v(0, 16), v(16, 0)], [[255 << 16; 3]; 3], Fill::Rows);
/// assert!(px[4 * 16 + 4] > 100);
/// ```
pub fn draw_quadratic<P: PixelFormat, T: Target<P>, Z: DepthMode>(
    target: &mut T,
    v: [ScreenVertex; 3],
    mid: [[i32; 3]; 3],
    fill: Fill,
) -> u32 {
    draw_quadratic_div::<P, T, Z, Exact>(target, v, mid, fill)
}

/// [`draw_quadratic`] with the setup's and the fit's reciprocals taken through the
/// divider `D` ([`setup_div`], [`Quad::fit_div`]; [`draw_quadratic`] is
/// `draw_quadratic_div` with [`Exact`]). Coverage does not depend on `D`.
///
/// ```
/// use fixshade::divide::{Exact, ShiftAdd};
/// use fixshade::raster::quadratic::{draw_quadratic, draw_quadratic_div, Fill};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::ScreenVertex;
/// use fixshade::target::{Framebuffer, Gray8};
/// fn draw(approx: bool) -> [u8; 16 * 16] {
///     let mut px = [0u8; 16 * 16];
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 16, 16).unwrap();
///     let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [0; 3] };
///     let (t, m) = ([v(0, 0), v(0, 16), v(16, 0)], [[255 << 16; 3]; 3]);
///     if approx {
///         draw_quadratic_div::<Gray8, _, NoDepth, ShiftAdd<8>>(&mut fb, t, m, Fill::Rows);
///     } else {
///         draw_quadratic::<Gray8, _, NoDepth>(&mut fb, t, m, Fill::Rows);
///     }
///     px
/// }
/// let (e, a) = (draw(false), draw(true));
/// // The same pixels covered; the 4-bit-mantissa reciprocal only darkens.
/// assert!(e.iter().zip(&a).all(|(x, y)| (*x == 0) == (*y == 0) && y <= x));
/// ```
pub fn draw_quadratic_div<P: PixelFormat, T: Target<P>, Z: DepthMode, D: Divide>(
    target: &mut T,
    v: [ScreenVertex; 3],
    mid: [[i32; 3]; 3],
    fill: Fill,
) -> u32 {
    if super::vertex::outside_guard(arrays::map(v, |p| (p.x, p.y))) {
        return 0;
    }
    let (Some(s), Some(q)) = (setup_div::<D>(v), Quad::fit_div::<D>(v, mid)) else {
        return 0;
    };
    draw_setup_quad::<P, T, Z>(target, &s, &q, fill)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rng(seed: &mut u64) -> i64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 33) as i64
    }

    /// The exact interpolant (rational, in i128 scaled by det²) at a point given in
    /// Q12.4 as barycentrics of the six nodes: checks the fit at the nodes whose
    /// coordinates are pixel centres.
    #[test]
    fn reciprocal_division_rounds_to_nearest() {
        let mut seed = 3u64;
        for _ in 0..20000 {
            let bits_d = (rng(&mut seed) % 71) as u32;
            let bits_n = (rng(&mut seed) % 98) as u32;
            let wide = |s: &mut u64, bits: u32| -> i128 {
                let v = ((rng(s) as u128) << 64 | (rng(s) as u128) << 32 | rng(s) as u128)
                    & ((1u128 << bits) - 1);
                v as i128
            };
            let d = wide(&mut seed, bits_d).max(1) * if rng(&mut seed) % 2 == 0 { 1 } else { -1 };
            let n = wide(&mut seed, bits_n) * if rng(&mut seed) % 2 == 0 { 1 } else { -1 };
            let got = Recip::new::<Exact>(d).div(n);
            // |got − n/d| ≤ ½ (+ 2^-29), i.e. |2·got·d − 2n| ≤ |d|(1 + 2^-28).
            let err = (2 * got * d - 2 * n).unsigned_abs();
            assert!(
                err <= d.unsigned_abs() + (d.unsigned_abs() >> 28) + 1,
                "{n} / {d} = {got}"
            );
        }
    }

    #[test]
    fn passes_through_the_six_samples() {
        let mut seed = 7u64;
        let mut worst = 0i64;
        for _ in 0..3000 {
            // Vertices on even pixel centres so the midpoints are pixel centres too.
            let p = |s: &mut u64| (rng(s) % 600 - 300) as i32 * 2;
            let mut v = [ScreenVertex::default(); 3];
            for vk in v.iter_mut() {
                vk.x = 16 * p(&mut seed) + 8;
                vk.y = 16 * p(&mut seed) + 8;
                vk.c = core::array::from_fn(|_| (rng(&mut seed) % (255 << 16)) as i32);
            }
            let mid: [[i32; 3]; 3] = core::array::from_fn(|_| {
                core::array::from_fn(|_| (rng(&mut seed) % (255 << 16)) as i32)
            });
            let Some(q) = Quad::fit(v, mid) else { continue };
            let px = |x: i32| (x - 8) / 16;
            for k in 0..3 {
                let a = v[k];
                let b = v[(k + 1) % 3];
                let got = q.at(px(a.x), px(a.y));
                let gm = q.at(px((a.x + b.x) / 2), px((a.y + b.y) / 2));
                for ch in 0..3 {
                    // Compare in Q.16 (the bias ½ of Q.40 removed).
                    let e = ((got[ch] - (1 << 39)) >> 24) - a.c[ch] as i64;
                    let em = ((gm[ch] - (1 << 39)) >> 24) - mid[k][ch] as i64;
                    worst = worst.max(e.abs()).max(em.abs());
                }
            }
        }
        // 2^-13 channel units is 8 Q.16 units; the >> floors.
        extern crate std;
        std::println!("largest deviation at the six nodes: {worst} Q.16 units");
        assert!(worst <= 9, "worst {worst}");
    }
}
