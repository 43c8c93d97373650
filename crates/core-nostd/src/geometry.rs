//! Geometry: meshes in flash and the projection from clip space to the screen.
//!
//! A [`Mesh`] borrows `&'static` (or any) slices of Q16.16 positions, Q2.14 normals and
//! `u16` index triples, so a baked model lives in flash and costs no RAM.
//!
//! ```
//! use fixshade::fixed::{Q16_16, Q2_14};
//! use fixshade::geometry::Mesh;
//! static POS: [[Q16_16; 3]; 3] = [
//!     [Q16_16::ZERO, Q16_16::ZERO, Q16_16::ZERO],
//!     [Q16_16::ONE, Q16_16::ZERO, Q16_16::ZERO],
//!     [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
//! ];
//! static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
//! static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
//! let mesh = Mesh::new(&POS, &NRM, &TRI).unwrap();
//! assert_eq!(mesh.triangles().len(), 1);
//! ```

use crate::fixed::{Q16_16, Q2_14};
use crate::math::{leading_zeros, mul_wide, recip_q61, Vec3};
use crate::raster::GUARD;

/// Largest |coordinate| of a mesh position (keeps the per-vertex `i64` transform
/// from overflowing; see [`crate::math::ClipMatrix::transform`]).
pub const MAX_COORD: i32 = 1 << 14;

/// Why a mesh was refused.
///
/// ```
/// use fixshade::fixed::{Q16_16, Q2_14};
/// use fixshade::geometry::{Mesh, MeshError};
/// let p = [[Q16_16::ZERO; 3]; 3];
/// let n = [[Q2_14::ONE; 3]; 3];
/// assert_eq!(Mesh::new(&p, &n, &[[0, 1, 3]]).unwrap_err(), MeshError::IndexOutOfRange(0));
/// assert_eq!(Mesh::new(&p, &n[..2], &[]).unwrap_err(), MeshError::NormalCount);
/// assert_eq!(MeshError::IndexOutOfRange(0).to_string(), "triangle 0 refers to a missing vertex");
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum MeshError {
    /// Positions and normals differ in count.
    NormalCount,
    /// More than 65535 vertices.
    TooManyVertices,
    /// A triangle refers to a vertex that does not exist (the triangle's number).
    IndexOutOfRange(usize),
    /// A position lies outside ±16384 (the vertex's number).
    CoordinateOutOfRange(usize),
}

impl core::fmt::Display for MeshError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MeshError::NormalCount => f.write_str("positions and normals differ in count"),
            MeshError::TooManyVertices => f.write_str("more than 65535 vertices"),
            MeshError::IndexOutOfRange(t) => write!(f, "triangle {t} refers to a missing vertex"),
            MeshError::CoordinateOutOfRange(v) => {
                write!(f, "vertex {v} lies outside the coordinate range ±16384")
            }
        }
    }
}

/// A validated triangle mesh. Triangles are counter-clockwise seen from their front.
///
/// ```
/// use fixshade::fixed::{Q16_16, Q2_14};
/// use fixshade::geometry::Mesh;
/// let q = Q16_16::from_int;
/// let z = Q2_14::from_bits(0);
/// // One triangle in the z = 0 plane, facing +z; the slices can be `static`s in flash.
/// static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
/// let positions = [[q(-1), q(-1), q(0)], [q(1), q(-1), q(0)], [q(0), q(1), q(0)]];
/// let normals = [[z, z, Q2_14::ONE]; 3];
/// let mesh = Mesh::new(&positions, &normals, &TRI).unwrap();
/// assert_eq!(mesh.triangles().len(), 1);
/// assert_eq!(mesh.positions()[2][1], q(1));
/// assert_eq!(mesh.normals()[0][2], Q2_14::ONE);
/// ```
#[derive(Copy, Clone, Debug)]
pub struct Mesh<'a> {
    positions: &'a [Vec3],
    normals: &'a [[Q2_14; 3]],
    triangles: &'a [[u16; 3]],
}

impl<'a> Mesh<'a> {
    /// Checks and wraps the slices.
    pub fn new(
        positions: &'a [Vec3],
        normals: &'a [[Q2_14; 3]],
        triangles: &'a [[u16; 3]],
    ) -> Result<Mesh<'a>, MeshError> {
        if positions.len() != normals.len() {
            return Err(MeshError::NormalCount);
        }
        if positions.len() > 65535 {
            return Err(MeshError::TooManyVertices);
        }
        let lim = Q16_16::from_int(MAX_COORD);
        if let Some(i) = positions
            .iter()
            .position(|p| p.iter().any(|c| c.abs() >= lim))
        {
            return Err(MeshError::CoordinateOutOfRange(i));
        }
        let n = positions.len();
        if let Some(t) = triangles
            .iter()
            .position(|t| t.iter().any(|i| *i as usize >= n))
        {
            return Err(MeshError::IndexOutOfRange(t));
        }
        Ok(Mesh {
            positions,
            normals,
            triangles,
        })
    }

    /// Vertex positions.
    pub fn positions(&self) -> &'a [Vec3] {
        self.positions
    }

    /// Vertex normals.
    pub fn normals(&self) -> &'a [[Q2_14; 3]] {
        self.normals
    }

    /// Triangles.
    pub fn triangles(&self) -> &'a [[u16; 3]] {
        self.triangles
    }
}

/// The viewport: clip coordinates to Q12.4 screen coordinates and Q16.16 depth.
///
/// ```
/// use fixshade::geometry::Viewport;
/// let vp = Viewport { width: 320, height: 240 };
/// // NDC (-1, 1) is the top-left corner of the frame (Q12.4 pixels), depth 0 at z = -w.
/// assert_eq!(vp.project([-1 << 20, 1 << 20, -1 << 20, 1 << 20]), Some((0, 0, 0)));
/// // Behind the eye (w ≤ 0): no projection.
/// assert_eq!(vp.project([0, 0, 0, -1]), None);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Viewport {
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
}

/// Depth scale: d in [0, 1] maps to `d · DEPTH_SCALE` in Q16.16 (u16 values 0..=65534;
/// 65535 is the cleared "far" value that nothing reaches).
pub const DEPTH_SCALE: i64 = 65534 << 16;

impl Viewport {
    /// Projects homogeneous clip coordinates (any common scale, `w > 0`). Returns
    /// `(x, y, z)` with x, y in Q12.4 and z in Q16.16, or `None` if `w ≤ 0`, the depth
    /// is outside [0, 1], or the point lies outside the guard band.
    ///
    /// The coordinates are first shifted so the largest is below 2³⁰ (relative
    /// precision 2⁻²⁹; projection is scale-free), then divided by `w` with one
    /// reciprocal and 32×32-bit products (see `divide`): positions round to the
    /// nearest 1/16 pixel, the depth is within 11 units (Q16.16) of the exact one.
    ///
    /// ```
    /// use fixshade::geometry::Viewport;
    /// let vp = Viewport { width: 320, height: 240 };
    /// // The centre of NDC lands on the centre of the frame, depth halfway.
    /// let (x, y, z) = vp.project([0, 0, 0, 1 << 20]).unwrap();
    /// assert_eq!((x, y), (160 * 16, 120 * 16));
    /// assert!(z.abs_diff(32767 << 16) <= 11);
    /// ```
    #[inline]
    pub fn project(&self, c: [i64; 4]) -> Option<(i32, i32, u32)> {
        let [_, _, z, w] = c;
        if w <= 0 || z < -w || z > w {
            return None;
        }
        let [x, y, z, w] = normalize_clip(c);
        let (sx, sy, sz) = self.divide(x, y, z, w);
        if sx.unsigned_abs() >= GUARD as u64 || sy.unsigned_abs() >= GUARD as u64 {
            return None;
        }
        Some((sx as i32, sy as i32, sz as u32))
    }

    /// The perspective division of normalised coordinates (|·| < 2³⁰, `w > 0`,
    /// `−w ≤ z ≤ w`) with one reciprocal instead of three divisions, and no 64-bit
    /// division: `w` is shifted left by `s` into [2³⁰, 2³¹) and `R = recip_q61`,
    /// within 2 units of `2⁶¹/(w·2ˢ)`, so `1/w = R·2^(s − 61)` to 2⁻²⁹ relatively.
    ///
    /// Each screen coordinate is `k·(1 + c/w)` for a scale `k` (`8·W` and `8·H` in
    /// Q12.4 with `c = x` and `c = −y`; `32767·2¹⁶` for the Q16.16 depth with
    /// `c = z`): `k·R` (below 2⁴⁷, from a 32×16-bit product) is cut to 31 bits by a
    /// per-axis shift `b`, and `c·(k·R >> b)` (below 2⁶¹, [`mul_wide`]) is shifted
    /// down by `61 − s − b`. Positions round to nearest, the depth truncates. The
    /// positions are within 2⁻²⁷ of a unit of the exact quotient where |c/w| ≤ 1
    /// (the reciprocal's 2⁻²⁹ and the cut; in the guard band 2⁻¹⁵), so the rounding
    /// to 1/16 pixel differs from exact division only for values that close to a
    /// half; the depth is within 11 units (Q16.16; 2⁻¹² of a u16 step) of the exact
    /// floor (tested), and exactly 0 on the near plane.
    #[inline]
    pub(crate) fn divide(&self, x: i64, y: i64, z: i64, w: i64) -> (i64, i64, i64) {
        let w = w as u32; // 1 ≤ w < 2^30
        let s = leading_zeros(w) - 1; // 1..=30
        let r = recip_q61(w << s);
        // k·(1 + c/w) with k < 2^16: k·r < 2^47; shifted by the bits of k, below 2^31.
        let scaled = |k: u32, c: i64, round: bool| -> i64 {
            let b = 32 - leading_zeros(k);
            let kr = (mul_u32_u16(r, k) >> b) as i32;
            let sh = 61 - s - b; // 15..=56
            let bias = if round { 1i64 << (sh - 1) } else { 0 };
            k as i64 + ((mul_wide(c as i32, kr) + bias) >> sh)
        };
        let sx = scaled(8 * self.width, x, true);
        let sy = scaled(8 * self.height, -y, true);
        // The depth: (z + w)/w · 32767·2^16, from z + w in [0, 2w] (so the near
        // plane is exactly 0), kept in [0, DS].
        let kz = mul_u32_u16(r, 32767) >> 15; // (32767·2^16·r) >> 31 < 2^31
        let sz = mul_wide((z + w as i64) as i32, kz as i32) >> (30 - s);
        (sx, sy, sz.clamp(0, DEPTH_SCALE))
    }
}

/// The product of `a` and `b < 2¹⁶` as `u64` from two 32×16-bit products
/// (`ah·b` and `al·b` both fit `u32`): no 64-bit multiply on any core.
#[inline(always)]
pub(crate) fn mul_u32_u16(a: u32, b: u32) -> u64 {
    debug_assert!(b < 1 << 16);
    ((((a >> 16) * b) as u64) << 16) + ((a & 0xFFFF) * b) as u64
}

/// Shifts homogeneous coordinates right until every |component| < 2³⁰.
///
/// ```
/// use fixshade::geometry::normalize_clip;
/// assert_eq!(normalize_clip([1 << 40, 0, -(1 << 39), 1 << 38]), [1 << 29, 0, -(1 << 28), 1 << 27]);
/// assert_eq!(normalize_clip([5, 6, 7, 8]), [5, 6, 7, 8]);
/// ```
#[inline]
pub fn normalize_clip(c: [i64; 4]) -> [i64; 4] {
    let max = c.iter().fold(0u64, |m, v| m | v.unsigned_abs());
    let bits = 64 - leading_zeros_u64(max) as i32;
    let shift = bits - 30;
    if shift > 0 {
        c.map(|v| v >> shift)
    } else {
        c
    }
}

/// Leading zeros of a `u64` from two 32-bit counts ([`leading_zeros`]).
#[inline]
fn leading_zeros_u64(v: u64) -> u32 {
    let hi = (v >> 32) as u32;
    if hi != 0 {
        leading_zeros(hi)
    } else {
        32 + leading_zeros(v as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `⌊n/d + ½⌋` and `⌊n/d⌋` exactly (d > 0).
    fn round_div(n: i128, d: i128) -> i128 {
        (2 * n + d).div_euclid(2 * d)
    }

    /// The division by one reciprocal against exact rational division: positions
    /// within 1/16 pixel of the exact rounding, and equal to it unless the exact
    /// quotient lies within 2⁻¹⁴ of a half (the bound above for |c/w| ≤ 1 and
    /// 8·W ≤ 2¹⁵); the Q16.16 depth within 11 units of the exact floor (below
    /// 2³²·(2⁻²⁹ + 2⁻³¹) from the reciprocal and the cut, one from the truncation):
    /// 2⁻¹² of a u16 step.
    #[test]
    fn divide_matches_exact_division() {
        let mut seed = 0x1234_5678_9abc_def1u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        // A position that differs from the exact rounding of n/d: n/d lies within
        // 2^-14 of a half, |2·(n mod d) − d| < d·2^-13.
        let near_half = |n: i128, d: i128| (2 * n.rem_euclid(d) - d).abs() * (1 << 13) < d;
        let mut differ = 0;
        for k in 0..400_000u32 {
            let (width, height) = (1 + (next() % 4096) as u32, 1 + (next() % 4096) as u32);
            let vp = Viewport { width, height };
            let w = ((next() >> 34) as i64 >> (k % 29)).max(1); // 1 ≤ w < 2^30
            let c = |r: u64| (r % (2 * w as u64 + 1)) as i64 - w;
            let (x, y, z) = (c(next()), c(next()), c(next()));
            let (sx, sy, sz) = vp.divide(x, y, z, w);
            let (nx, ny) = (
                8 * width as i128 * (x + w) as i128,
                8 * height as i128 * (w - y) as i128,
            );
            let (ex, ey) = (round_div(nx, w as i128), round_div(ny, w as i128));
            let ez = ((z + w) as i128 * (DEPTH_SCALE >> 1) as i128).div_euclid(w as i128);
            for (got, want, n) in [(sx, ex, nx), (sy, ey, ny)] {
                assert!((got as i128 - want).abs() <= 1, "{x} {y} {w}");
                if got as i128 != want {
                    assert!(near_half(n, w as i128), "{n}/{w}: {got} vs {want}");
                    differ += 1;
                }
            }
            assert!((sz as i128 - ez).abs() <= 11, "z {z} w {w}: {sz} vs {ez}");
        }
        // Exact ties (small w) and near-ties are rare.
        assert!(
            differ < 1000,
            "{differ} positions differ from exact rounding"
        );
    }
}
