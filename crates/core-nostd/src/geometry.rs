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
use crate::math::Vec3;
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
    /// precision 2⁻²⁹; projection is scale-free). Then `8·W·(x + w)` < 2³¹·2¹⁵ and
    /// `(z + w)·65534·2¹⁵` < 2³¹·2³¹ fit `i64`.
    ///
    /// ```
    /// use fixshade::geometry::Viewport;
    /// let vp = Viewport { width: 320, height: 240 };
    /// // The centre of NDC lands on the centre of the frame, depth halfway.
    /// assert_eq!(vp.project([0, 0, 0, 1 << 20]), Some((160 * 16, 120 * 16, 32767 << 16)));
    /// ```
    #[inline]
    pub fn project(&self, c: [i64; 4]) -> Option<(i32, i32, u32)> {
        let [x, y, z, w] = normalize_clip(c);
        if w <= 0 || z < -w || z > w {
            return None;
        }
        let (sx, sy, sz) = self.divide(x, y, z, w);
        if sx.abs() >= GUARD as i64 || sy.abs() >= GUARD as i64 {
            return None;
        }
        Some((sx as i32, sy as i32, sz as u32))
    }

    /// The perspective division of normalised coordinates (|·| < 2³⁰, `w > 0`,
    /// `−w ≤ z ≤ w`) with one reciprocal `r = ⌊2⁶² / w⌋` instead of three divisions.
    /// The numerators `8·W·(x + w)` are below 2⁴⁶ and `(z + w)·65534·2¹⁵` below 2⁶²;
    /// their products with `r` ≤ 2⁶² are below 2¹²⁴ and fit `i128`. The quotient's error is below
    /// 2⁻¹⁶ of a unit, so the rounding to 1/16 pixel differs from exact division
    /// only for values within 2⁻¹⁶ of a half.
    #[inline]
    pub(crate) fn divide(&self, x: i64, y: i64, z: i64, w: i64) -> (i64, i64, i64) {
        let r = ((1u64 << 62) / w as u64) as i128;
        let round = |n: i64| ((n as i128 * r + (1i128 << 61)) >> 62) as i64;
        let sx = round(8 * self.width as i64 * (x + w));
        let sy = round(8 * self.height as i64 * (w - y));
        let sz = ((((z + w) * (DEPTH_SCALE >> 1)) as i128 * r) >> 62) as i64;
        (sx, sy, sz)
    }
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
    let bits = 64 - max.leading_zeros() as i32;
    let shift = bits - 30;
    if shift > 0 {
        c.map(|v| v >> shift)
    } else {
        c
    }
}
