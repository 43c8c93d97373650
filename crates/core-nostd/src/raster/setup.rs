//! Triangle setup: sort the vertices, take one reciprocal of the determinant, and
//! derive the constant per-triangle increments of every attribute (seed 000 §2.1,
//! DESIGN.md method 1).
//!
//! With `dx1 = x1 − x0`, `dy1 = y1 − y0`, … (Q12.4) and `det = dx1·dy2 − dx2·dy1`,
//! an attribute `a` changes per pixel by
//! `Gx = 16·(Δa1·dy2 − Δa2·dy1) / det` along a row and `Gy = 16·(Δa2·dx1 − Δa1·dx2) / det`
//! down a column: the seed's `dI/dx`, the same on every scanline.
//!
//! Bounds: |dx|, |dy| < 2¹⁷ (guard band), so `det` < 2³⁵; |Δa| ≤ 2³² (depth), so each
//! numerator is below 2⁵⁴ and fits `i64`. The quotient uses one reciprocal
//! `inv = ⌊2⁶² / |det|⌋` and an `i128` product; its error is at most
//! `|num|/2⁶² + ½ ≤ 0.51` of the attribute's last bit.
//!
//! Every attribute value the rasterizer produces lies on the lattice
//! `V(x, y) = A + (x − xa)·Gx + (y − ya)·Gy` (wrapping `i32`) anchored at the pixel
//! `(xa, ya)` that holds the top vertex's first row. The anchor value `A` is the
//! exact plane value there to within one unit plus the rounding bias. Against the
//! exact plane the lattice is off by at most `0.51·(|x − xa| + |y − ya|) + 1` units,
//! i.e. below 4200 units (0.065 of an output step) anywhere inside a triangle of the
//! 4095-pixel range: the interpolated colour is within 0.5 + 0.065 < 1 output step
//! of the exact value (the bound the accuracy tests check).

use super::edge::first_row;
use super::ScreenVertex;
use crate::divide::{wide_recip, Divide, Exact};

/// Number of interpolated attributes: three colour channels and depth.
pub const ATTRS: usize = 4;

/// Rounding bias added to the anchor so that `value >> 16` rounds to nearest.
pub const ROUND_BIAS: i32 = 1 << 15;

/// A triangle ready for the edge walker.
///
/// ```
/// use fixshade::raster::setup::{setup, ROUND_BIAS};
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, r: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [r << 16, 0, 0] };
/// // Red 0 at the left, 160 at x = 16 pixels: 10 per pixel, constant over the triangle.
/// let s = setup([v(0, 16, 0), v(0, 0, 0), v(16, 0, 160)]).unwrap();
/// assert_eq!(s.v[0].y, 0); // sorted: top first
/// assert_eq!(s.gx[0], 10 << 16);
/// assert_eq!(s.gy[0], 0);
/// assert_eq!(s.at(3, 2)[0], (35 << 16) + ROUND_BIAS); // 10·3.5 at the pixel centre
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Setup {
    /// Vertices sorted by y (then x): top, middle, bottom.
    pub v: [ScreenVertex; 3],
    /// True if the middle vertex lies left of the long edge top→bottom.
    pub mid_left: bool,
    /// Per-pixel increments along x (colour channels in Q.16 output units, depth Q16.16).
    pub gx: [i32; ATTRS],
    /// Per-row increments along y.
    pub gy: [i32; ATTRS],
    /// Lattice anchor pixel.
    pub anchor: (i32, i32),
    /// Attribute values at the anchor pixel centre, rounding bias included.
    pub a: [i32; ATTRS],
}

impl Setup {
    /// Attribute values at pixel `(x, y)` of the lattice (wrapping arithmetic: the
    /// result is exact modulo 2³², and the true value at a covered pixel fits `i32`,
    /// so it is exact there).
    #[inline]
    pub fn at(&self, x: i32, y: i32) -> [i32; ATTRS] {
        let dx = x.wrapping_sub(self.anchor.0);
        let dy = y.wrapping_sub(self.anchor.1);
        core::array::from_fn(|k| {
            self.a[k]
                .wrapping_add(dx.wrapping_mul(self.gx[k]))
                .wrapping_add(dy.wrapping_mul(self.gy[k]))
        })
    }
}

fn attrs(v: &ScreenVertex) -> [i64; ATTRS] {
    [v.c[0] as i64, v.c[1] as i64, v.c[2] as i64, v.z as i64]
}

/// The shared core of a triangle's setup: the edge deltas from the top vertex and the
/// one reciprocal of the determinant, signed. Used by [`setup`] and by the Phong
/// planes, so a Phong triangle divides once, like any other.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Det {
    dx1: i64,
    dy1: i64,
    dx2: i64,
    dy2: i64,
    /// `sign(det)·⌊2⁶²/|det|⌋`: |inv| ≤ 2⁶² fits `i64`, so each increment is one
    /// signed 64×64→128 multiply.
    inv: i64,
}

impl Det {
    /// `None` for a zero-area triangle. Vertices sorted, in the guard band.
    ///
    /// The reciprocal goes through `D`: [`Exact`] keeps the full `⌊2⁶²/|det|⌋`
    /// (bit-identical to the setup before the seam); any other variant rounds
    /// `|det|` up to its mantissa and takes [`wide_recip`]: relative error at most
    /// `η = 2^(1−b) + (2E + 2)·2^b/2³⁰` (see there), never an over-estimate. Every
    /// increment inherits it, so a covered pixel's value moves from the exact one
    /// towards the top vertex's by at most `η` of their difference: it stays in
    /// range, within `η` times the triangle's attribute range of the exact value.
    fn new<D: Divide>(p: [(i32, i32); 3]) -> Option<Det> {
        let (dx1, dy1) = ((p[1].0 - p[0].0) as i64, (p[1].1 - p[0].1) as i64);
        let (dx2, dy2) = ((p[2].0 - p[0].0) as i64, (p[2].1 - p[0].1) as i64);
        let det = dx1 * dy2 - dx2 * dy1;
        if det == 0 {
            return None;
        }
        // |det| ≥ 1 and < 2^35: a u64 division (one hardware divide on 64-bit hosts).
        // Both branches give 1 ≤ inv ≤ 2^62: fits i64, and so does its negation.
        let inv = if D::EXACT {
            ((1u64 << 62) / det.unsigned_abs()) as i64
        } else {
            // ≤ 2^62 (the mantissa is at least 1), at least 1: the sign survives.
            wide_recip::<D>(det.unsigned_abs() as u128).scaled(62) as i64
        };
        Some(Det {
            dx1,
            dy1,
            dx2,
            dy2,
            inv: if det < 0 { -inv } else { inv },
        })
    }

    /// The per-pixel increments `(Gx, Gy)` of an attribute that changes by `d1` and
    /// `d2` from the top vertex to the others, with `extra` more fraction bits,
    /// rounded. |d| ≤ 2³², so each numerator is below 2⁵⁴ and, with |inv| ≤ 2⁶², the
    /// i128 product below 2¹¹⁶; the quotient is below 2^(55 + extra).
    #[inline]
    pub(crate) fn gradient(&self, d1: i64, d2: i64, extra: u32) -> (i128, i128) {
        let sh = 62 - extra;
        // |inv| ≤ 2^62 and |num| < 2^54 are both i64: one widening multiply.
        let inv = self.inv;
        let quot = |num: i64| (num as i128 * inv as i128 + (1 << (sh - 1))) >> sh;
        (
            quot(16 * (d1 * self.dy2 - d2 * self.dy1)),
            quot(16 * (d2 * self.dx1 - d1 * self.dx2)),
        )
    }
}

/// Sets up a triangle. Returns `None` for a zero-area triangle. Coordinates must lie
/// in the guard band (|x|, |y| < 2¹⁶); the clip stage guarantees it.
///
/// An increment is kept modulo 2³² (`i32` wrapping): a sliver may change an attribute
/// by more than 2³¹ units per pixel, but the lattice arithmetic is exact modulo 2³²
/// and the true value at every covered pixel fits, so the result there is still exact
/// to the bound above.
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32| ScreenVertex { x, y, z: 0, c: [0; 3] };
/// assert!(setup([v(0, 0), v(32, 0), v(0, 32)]).is_some());
/// assert!(setup([v(0, 0), v(16, 16), v(32, 32)]).is_none()); // collinear: zero area
/// ```
pub fn setup(v: [ScreenVertex; 3]) -> Option<Setup> {
    setup_div::<Exact>(v)
}

/// [`setup`] with the determinant's reciprocal taken through the divider `D`
/// ([`setup`] is `setup_div::<Exact>`).
///
/// ```
/// use fixshade::divide::{Exact, ShiftAdd};
/// use fixshade::raster::setup::{setup, setup_div};
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, r: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [r << 16, 0, 0] };
/// let t = [v(0, 0, 0), v(37, 5, 200), v(3, 29, 90)];
/// assert_eq!(setup_div::<Exact>(t), setup(t));
/// // An 8-term shift-and-add reciprocal never over-estimates: increments shrink a little.
/// let (e, a) = (setup(t).unwrap(), setup_div::<ShiftAdd<8>>(t).unwrap());
/// assert!(a.gx[0].abs() <= e.gx[0].abs() && a.gx[0].abs() * 10 > e.gx[0].abs() * 9);
/// ```
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn setup_div<D: Divide>(v: [ScreenVertex; 3]) -> Option<Setup> {
    setup_with_det_div::<D>(v).map(|(s, _)| s)
}

/// [`setup_div`], also returning its [`Det`] for further attribute planes.
/// Always inlined on hosted targets, so the set-up triangle is built where it is
/// used instead of being returned through memory; bare-metal targets keep one copy
/// (flash; see [`super::edge::EdgeStepper::new`]).
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn setup_with_det_div<D: Divide>(mut v: [ScreenVertex; 3]) -> Option<(Setup, Det)> {
    // Sorted by (y, x) with three compare-exchanges. Two vertices with equal keys
    // coincide, so the triangle has zero area and is rejected whatever their order.
    let key = |p: &ScreenVertex| (p.y, p.x);
    if key(&v[1]) < key(&v[0]) {
        v.swap(0, 1);
    }
    if key(&v[2]) < key(&v[1]) {
        v.swap(1, 2);
        if key(&v[1]) < key(&v[0]) {
            v.swap(0, 1);
        }
    }
    let det = Det::new::<D>(v.map(|p| (p.x, p.y)))?;
    let (a0, a1, a2) = (attrs(&v[0]), attrs(&v[1]), attrs(&v[2]));
    let mut gx = [0i64; ATTRS];
    let mut gy = [0i64; ATTRS];
    for k in 0..ATTRS {
        let (d1, d2) = (a1[k] - a0[k], a2[k] - a0[k]);
        if d1 != 0 || d2 != 0 {
            // The quotient is below 2^55 and fits i64.
            let (x, y) = det.gradient(d1, d2, 0);
            (gx[k], gy[k]) = (x as i64, y as i64);
        }
    }
    let anchor = (first_row(v[0].x), first_row(v[0].y));
    // Offsets of the anchor centre from the top vertex, in [0, 16) subpixels.
    let ox = (16 * anchor.0 + 8 - v[0].x) as i64;
    let oy = (16 * anchor.1 + 8 - v[0].y) as i64;
    // ox, oy < 16 and |g| < 2^55: the sum is below 2^60.
    let a = core::array::from_fn(|k| {
        let off = (ox * gx[k] + oy * gy[k] + 8) >> 4;
        (a0[k] + off + ROUND_BIAS as i64) as i32 // modulo 2^32 by design
    });
    let s = Setup {
        // y points down: the middle vertex is left of top→bottom when det < 0.
        mid_left: det.inv < 0,
        v,
        gx: gx.map(|g| g as i32), // modulo 2^32 by design
        gy: gy.map(|g| g as i32),
        anchor,
        a,
    };
    Some((s, det))
}
