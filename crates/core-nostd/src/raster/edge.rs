//! Edge stepping: the Obidnyk–Petukh evaluation-function stepper (seed 000 §4.3)
//! generalised to subpixel vertices.
//!
//! For an edge from `(x0, y0)` to `(x1, y1)` (Q12.4, `y0 < y1`) and the pixel row `y`
//! whose centre is `yc = 16y + 8`, the edge crosses the row at
//! `X(yc) = x0 + dx·(yc − y0)/dy`. The first pixel whose centre is at or right of
//! the crossing is `q = ⌈(X(yc) − 8) / 16⌉`: a pixel centre exactly on the edge counts
//! as right of it. Both sides of a triangle use the same `q`: the left boundary
//! includes pixel `q`, the right boundary excludes it, so a pixel centre exactly on
//! a shared edge belongs to exactly one of the two triangles (the top-left rule).
//!
//! With `N(y) = x0·dy + dx·(yc − y0) − 8·dy` and `D = 16·dy`, `q = ⌈N / D⌉` and the
//! evaluation function `r = q·D − N ∈ [0, D)`. Moving one row adds `16·dx = a·D + b`
//! (`0 ≤ b < D`) to `N`: `q` advances by `a`, `r` drops by `b`, and when `r` goes
//! negative it gains `D` back and `q` takes one extra step (the diagonal step of the
//! seed's stepper). With S = 0 subpixel bits this is exactly the seed's algorithm
//! with `OF = r`.
//!
//! Bounds: coordinates are within the guard band, |x|, |y| < 2¹⁶ (Q12.4 of ±4096
//! pixels), so `dy ≤ 2¹⁷`, `D ≤ 2²¹` and `16·|dx| ≤ 2²¹`: `q`, `r`, `a`, `b` fit `i32`.
//! The starting `N` needs up to 2³⁵ and is computed once in `i64`.

use crate::math::{div_rem_u32, mul_wide};

/// An edge being stepped row by row.
///
/// ```
/// use fixshade::raster::edge::EdgeStepper;
/// // The edge from (0, 0) to (4, 8) pixels (Q12.4), from pixel row 0: the crossing
/// // moves half a pixel per row, so q advances by one every other row.
/// let mut e = EdgeStepper::new((0, 0), (64, 128), 0);
/// let mut q = vec![e.q];
/// for _ in 0..5 {
///     e.step();
///     q.push(e.q);
/// }
/// assert_eq!(q, [0, 1, 1, 2, 2, 3]);
/// assert!(0 <= e.r && e.r < e.d);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct EdgeStepper {
    /// First pixel at or right of the edge on the current row.
    pub q: i32,
    /// Evaluation function, `0 ≤ r < d`.
    pub r: i32,
    /// `16·dy`.
    pub d: i32,
    /// Whole pixels per row (`⌊16·dx / d⌋`).
    pub a: i32,
    /// Remainder per row, `0 ≤ b < d`.
    pub b: i32,
}

/// `⌈n / d⌉` for `d > 0`.
#[inline]
pub(crate) fn ceil_div(n: i64, d: i64) -> i64 {
    -((-n).div_euclid(d))
}

impl EdgeStepper {
    /// The stepper of the edge `top → bottom` (`top.1 < bottom.1`) positioned on
    /// pixel row `y`.
    ///
    /// Always inlined on hosted targets: its fast paths branch on the data, and out
    /// of line the call and the spilled result cost more than the divisions they
    /// skip. Bare-metal targets (`target_os = "none"`) leave it to the compiler:
    /// every span method inlines the setup, and flash is the scarcer resource there
    /// (a Cortex-M0 image with every span method overflowed its 256 KiB).
    #[cfg_attr(not(target_os = "none"), inline(always))]
    #[cfg_attr(target_os = "none", inline)]
    pub fn new(top: (i32, i32), bottom: (i32, i32), y: i32) -> EdgeStepper {
        let dx = bottom.0 - top.0;
        let dy = bottom.1 - top.1;
        // d < 2^21.
        let d = 16 * dy;
        // N relative to the whole pixel left of the top vertex, so that near the top
        // vertex it fits i32 and an i32 division does: q = qx + ⌈N' / d⌉ with
        // N' = fx·dy + dx·(yc − y0) − 8·dy, fx = x0 − 16·qx in [0, 16).
        let qx = top.0 >> 4;
        let fx = top.0 & 15;
        // |off| < 2^18 within the guard band.
        let off = 16 * y + 8 - top.1;
        // ⌈n/d⌉ when it is 0 or 1 (the usual case on a small triangle): no division.
        let unit = |n: i32| {
            let q = (n > 0) as i32;
            (q, q * d - n)
        };
        // With |dx|, |off| < 2^15 every term fits i32 (|dx·off| < 2^30, the others
        // below 2^21): the usual case, no 64-bit product and no 64-bit comparison.
        let small = (dx.unsigned_abs() | off.unsigned_abs()) < 1 << 15;
        let n32 = ((fx - 8) * dy).wrapping_add(dx.wrapping_mul(off)); // used when small
        let n = if small {
            n32 as i64
        } else {
            ((fx - 8) * dy) as i64 + mul_wide(dx, off)
        };
        let (q, r) = if small && -d < n32 && n32 <= d {
            unit(n32)
        } else if -(d as i64) < n && n <= d as i64 {
            unit(n as i32)
        } else if n.unsigned_abs() < 1 << 31 {
            // ⌈n/d⌉ = −⌊−n/d⌋: an unsigned division of |n| by d, signs fixed.
            let (m, rem) = div_rem_u32(n.unsigned_abs() as u32, d as u32);
            let (m, rem) = (m as i32, rem as i32);
            if n > 0 {
                // ⌈n/d⌉ = m + (rem > 0); r = q·d − n = d − rem (or 0).
                if rem > 0 {
                    (m + 1, d - rem)
                } else {
                    (m, 0)
                }
            } else {
                // n < 0: ⌈n/d⌉ = −m, r = −m·d − n = rem.
                (-m, rem)
            }
        } else {
            let q = ceil_div(n, d as i64);
            (q as i32, (q * d as i64 - n) as i32)
        };
        // 16·|dx| < 2^21: the step division fits 32 bits.
        let step = 16 * dx;
        // ⌊step/d⌋ without a division when it is 0 or −1 (|dx| ≤ dy, the usual case).
        let a = if (0..d).contains(&step) {
            0
        } else if (-d..0).contains(&step) {
            -1
        } else {
            let (m, rem) = div_rem_u32(step.unsigned_abs(), d as u32);
            if step >= 0 {
                m as i32
            } else {
                -(m as i32) - (rem != 0) as i32
            }
        };
        let b = step - a * d;
        EdgeStepper {
            q: qx + q,
            r,
            d,
            a,
            b,
        }
    }

    /// Moves to the next row; returns true if `q` took the extra (diagonal) step.
    #[inline(always)]
    pub fn step(&mut self) -> bool {
        self.q += self.a;
        self.r -= self.b;
        if self.r < 0 {
            self.r += self.d;
            self.q += 1;
            true
        } else {
            false
        }
    }
}

/// Vertex deltas below this many subpixels (128 pixels) make a small triangle
/// (the triangle setup's 32-bit path).
pub(crate) const SMALL: i32 = 1 << 11;

/// Whether every vertex of `xy` lies within [`SMALL`] subpixels of the first one,
/// in both coordinates (then any two are within 2¹² of each other).
#[inline(always)]
pub(crate) fn is_small([t, m, b]: [(i32, i32); 3]) -> bool {
    // d + 2^11 is in [0, 2^12) exactly for d in [−2^11, 2^11) (|d| < 2^17 in the
    // guard band: no overflow); any other d sets a bit at 2^12 or above (or the
    // sign).
    let h = SMALL;
    let spread = (m.0 - t.0 + h) | (m.1 - t.1 + h) | (b.0 - t.0 + h) | (b.1 - t.1 + h);
    (spread as u32) < 2 * h as u32
}

/// The first pixel row whose centre is at or below `y` (Q12.4): `⌈(y − 8) / 16⌉`.
///
/// ```
/// use fixshade::raster::edge::first_row;
/// // Row 2's centre is at y = 2.5 pixels (40 in Q12.4).
/// assert_eq!(first_row(40), 2);
/// assert_eq!(first_row(41), 3);
/// assert_eq!(first_row(-7), 0);
/// assert_eq!(first_row(-8), -1); // row −1's centre
/// ```
#[inline]
pub fn first_row(y: i32) -> i32 {
    // ⌈(y − 8)/16⌉ = ⌊(y + 7)/16⌋: an arithmetic shift (in i64, so no y overflows).
    ((y as i64 + 7) >> 4) as i32
}

/// [`first_row`] of a vertex coordinate in the guard band (|y| <
/// [`GUARD`](super::GUARD) = 2¹⁶, as a set-up triangle's): `y + 7` stays far from
/// overflow there, so the shift is 32-bit (two instructions on the Cortex-M cores,
/// against five in `i64`). The walks and the binning of set-up triangles call it
/// per triangle and per band.
#[inline(always)]
pub(crate) fn first_row_in_guard(y: i32) -> i32 {
    // |y| < 2^16: y + 7 < 2^17, exact. (The clip stage keeps every set-up vertex
    // inside; only y > i32::MAX − 7 would wrap, to a wrong row, never a panic.)
    y.wrapping_add(7) >> 4
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact reference: ⌈(X(yc) − 8)/16⌉ with rational arithmetic.
    fn exact_q(top: (i32, i32), bottom: (i32, i32), y: i32) -> i32 {
        let (dx, dy) = ((bottom.0 - top.0) as i64, (bottom.1 - top.1) as i64);
        let num = top.0 as i64 * dy + dx * (16 * y as i64 + 8 - top.1 as i64) - 8 * dy;
        let den = 16 * dy;
        // ceil for positive den
        let q = num / den;
        (if q * den < num { q + 1 } else { q }) as i32
    }

    #[test]
    fn stepping_matches_direct_evaluation() {
        let mut seed = 12345u64;
        let mut rnd = |m: i64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) as i64 % (2 * m)) - m
        };
        for _ in 0..2000 {
            let top = (rnd(60000) as i32, rnd(60000) as i32);
            let mut bottom = (rnd(60000) as i32, rnd(60000) as i32);
            if bottom.1 <= top.1 {
                bottom.1 = top.1 + 1 + (rnd(3000).unsigned_abs() as i32);
            }
            let y0 = first_row(top.1);
            let mut e = EdgeStepper::new(top, bottom, y0);
            for y in y0..first_row(bottom.1).min(y0 + 300) {
                assert_eq!(e.q, exact_q(top, bottom, y), "{top:?} {bottom:?} row {y}");
                assert!(e.r >= 0 && e.r < e.d);
                e.step();
            }
        }
    }

    #[test]
    fn is_small_takes_deltas_within_2_11() {
        assert!(!is_small([(0, 0), (SMALL, 0), (0, 5)]));
        assert!(!is_small([(0, 0), (3, -SMALL - 1), (0, 5)]));
        assert!(is_small([(0, 0), (SMALL - 1, -SMALL), (0, 5)]));
        assert!(is_small([
            (100, 100),
            (100 - SMALL, 100 + SMALL - 1),
            (99, 101)
        ]));
    }

    #[test]
    fn integer_vertices_reduce_to_the_seed_stepper() {
        // Vertices on pixel centres (16k + 8): a 45° edge advances one pixel a row.
        let mut e = EdgeStepper::new((8, 8), (16 * 10 + 8, 16 * 10 + 8), 0);
        for y in 0..10 {
            assert_eq!(e.q, y);
            e.step();
        }
    }

    #[test]
    fn first_row_in_guard_is_first_row_over_the_guard_band() {
        let g = crate::raster::GUARD;
        assert_eq!(g, 1 << 16);
        for y in -g + 1..g {
            assert_eq!(first_row_in_guard(y), first_row(y), "y = {y}");
        }
    }

    #[test]
    fn first_row_uses_pixel_centres() {
        assert_eq!(first_row(8), 0); // centre of row 0 exactly on y: included
        assert_eq!(first_row(9), 1);
        assert_eq!(first_row(-8), -1); // row -1 has its centre at -8
        assert_eq!(first_row(-9), -1);
        assert_eq!(first_row(-7), 0);
        assert_eq!(first_row(-24), -2);
    }
}
