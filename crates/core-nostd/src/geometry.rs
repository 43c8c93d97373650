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
use crate::math::{
    leading_zeros, mul_hi, mul_hi_estimate, mul_hi_k, mul_wide, recip_q61, recip_refined, Mat4,
    Vec3, ZFromW,
};
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
    bound: i32,
}

impl<'a> Mesh<'a> {
    /// Checks and wraps the slices. A `const fn`: a mesh in flash can be checked
    /// when the firmware is compiled (a `static` built by a `const` block that
    /// fails to compile on an invalid mesh), and then costs nothing at run time.
    ///
    /// ```
    /// use fixshade::fixed::{Q16_16, Q2_14};
    /// use fixshade::geometry::Mesh;
    /// const fn q(v: i32) -> Q16_16 {
    ///     Q16_16::from_int(v)
    /// }
    /// const N: Q2_14 = Q2_14::ONE;
    /// const Z: Q2_14 = Q2_14::from_bits(0);
    /// static P: [[Q16_16; 3]; 3] = [[q(-1), q(-1), q(0)], [q(1), q(-1), q(0)], [q(0), q(1), q(0)]];
    /// static NORMALS: [[Q2_14; 3]; 3] = [[Z, Z, N]; 3];
    /// static T: [[u16; 3]; 1] = [[0, 1, 2]];
    /// static MESH: Mesh<'static> = match Mesh::new(&P, &NORMALS, &T) {
    ///     Ok(m) => m,
    ///     Err(_) => panic!("not a valid mesh"), // a compile error, not a run-time panic
    /// };
    /// assert_eq!(MESH.bound(), 1 << 16);
    /// ```
    pub const fn new(
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
        // `while` loops: iterators are not `const`.
        let lim = Q16_16::from_int(MAX_COORD).to_bits();
        let mut bound = 0;
        let mut i = 0;
        while i < positions.len() {
            let mut k = 0;
            while k < 3 {
                // |c| below 2^30 after this test (saturating: i32::MIN fails it).
                let c = positions[i][k].to_bits().saturating_abs();
                if c >= lim {
                    return Err(MeshError::CoordinateOutOfRange(i));
                }
                if c > bound {
                    bound = c;
                }
                k += 1;
            }
            i += 1;
        }
        let n = positions.len();
        let mut t = 0;
        while t < triangles.len() {
            let [a, b, c] = triangles[t];
            if a as usize >= n || b as usize >= n || c as usize >= n {
                return Err(MeshError::IndexOutOfRange(t));
            }
            t += 1;
        }
        Ok(Mesh {
            positions,
            normals,
            triangles,
            bound,
        })
    }

    /// The largest |coordinate| of the positions, raw Q16.16 (below 2³⁰).
    ///
    /// ```
    /// use fixshade::fixed::{Q16_16, Q2_14};
    /// use fixshade::geometry::Mesh;
    /// let p = [[Q16_16::from_int(-3), Q16_16::ONE, Q16_16::ZERO]];
    /// let n = [[Q2_14::ONE; 3]];
    /// assert_eq!(Mesh::new(&p, &n, &[]).unwrap().bound(), 3 << 16);
    /// ```
    pub const fn bound(&self) -> i32 {
        self.bound
    }

    /// This mesh with [`Self::bound`] raised to `bound` (at most the coordinate
    /// limit): for a chunk of a larger mesh, the whole mesh's bound, so that the
    /// vertex stage, whose fixed-point scales follow the bound, transforms the
    /// chunk's vertices to exactly the bits the whole mesh's get (a board drawing
    /// a mesh chunk by chunk then draws the whole frame's pixels).
    ///
    /// ```
    /// use fixshade::fixed::{Q16_16, Q2_14};
    /// use fixshade::geometry::Mesh;
    /// let p = [[Q16_16::ONE, Q16_16::ZERO, Q16_16::ZERO]];
    /// let n = [[Q2_14::ONE; 3]];
    /// let m = Mesh::new(&p, &n, &[]).unwrap();
    /// assert_eq!(m.with_bound(3 << 16).bound(), 3 << 16);
    /// assert_eq!(m.with_bound(0).bound(), 1 << 16); // never lowered
    /// ```
    pub const fn with_bound(self, bound: i32) -> Mesh<'a> {
        let limit = Q16_16::from_int(MAX_COORD).to_bits() - 1;
        // `bound.clamp(self.bound, limit.max(self.bound))`, written out (`Ord::clamp`
        // is not `const`).
        let hi = if limit > self.bound {
            limit
        } else {
            self.bound
        };
        let bound = if bound < self.bound {
            self.bound
        } else if bound > hi {
            hi
        } else {
            bound
        };
        Mesh { bound, ..self }
    }

    /// Vertex positions.
    pub const fn positions(&self) -> &'a [Vec3] {
        self.positions
    }

    /// Vertex normals.
    pub const fn normals(&self) -> &'a [[Q2_14; 3]] {
        self.normals
    }

    /// Triangles.
    pub const fn triangles(&self) -> &'a [[u16; 3]] {
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

/// One screen axis of a [`Projector`]: `screen = k + round(k·c/w)` in Q12.4, with
/// `k` = 8·size (half the frame in sixteenths of a pixel).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
struct Axis {
    /// 8·size, 8..=2¹⁵.
    k: i32,
    /// `k` normalised to [2¹⁴, 2¹⁵), `k = k16·2^ks`, times 2¹⁶ (for [`mul_hi_k`]).
    kh: i32,
    /// Guard exponent: `k·2ᵍ ≥ GUARD + k + 1`, so `|c| ≥ w·2ᵍ` projects outside the
    /// guard band.
    g: u32,
    /// `sh − 32` and `2^(sh − 33)` for the product's shift `sh = 45 − g − ks`
    /// (41..=43 for every size 1..=4096).
    shift: u32,
    bias: i32,
}

impl Axis {
    fn new(size: u32) -> Axis {
        let k = 8 * size.clamp(1, 4096) as i32;
        let ks = 32 - (k as u32).leading_zeros() as i32 - 15;
        let k16 = if ks >= 0 { k >> ks } else { k << -ks };
        let mut g = 0;
        while ((k as i64) << g) < GUARD as i64 + k as i64 + 1 {
            g += 1;
        }
        let sh = 45 - g as i32 - ks;
        Axis {
            k,
            kh: k16 << 16,
            g,
            shift: (sh - 32) as u32,
            bias: 1 << (sh - 33),
        }
    }

    /// `k + ⌊c·k/w + ½⌋` exactly, from an estimate `s` within one of it (what the
    /// reciprocal gives, near a rounding half): the remainder `t = 2k·c + w −
    /// 2w·(s − k)` lies in `[0, 2w)` exactly for the right value, in `[−2w, 0)` for
    /// one too many and in `[2w, 4w)` for one too few. So `t + 2w` lies in `[0,
    /// 6w)`, below 2³² since `w < 2^w_bits ≤ 2²⁹` (`g ≥ 1`), and is taken modulo
    /// 2³² from 32-bit products ([`Self::exact_wide`] takes it in `i64`; both give
    /// the same bits, checked on every call in debug builds). The vertex stage and
    /// the clipper's projection both end here, so a vertex gets the same position
    /// on either path, and every position is the correctly rounded one.
    #[inline(always)]
    fn exact(&self, s: i32, c: i32, w: i32) -> i32 {
        debug_assert!(self.g >= 1 && (1..1 << 29).contains(&w));
        let w2 = (2 * w) as u32;
        let u = (2 * self.k as u32)
            .wrapping_mul(c as u32)
            .wrapping_add(w2 + w as u32)
            .wrapping_sub(w2.wrapping_mul((s - self.k) as u32));
        let e = if u < w2 {
            s - 1
        } else if u >= 2 * w2 {
            s + 1
        } else {
            s
        };
        debug_assert_eq!(e, self.exact_wide(s, c, w));
        e
    }

    /// [`Self::exact`] with the remainder in `i64` (`|2k·c|` < 2¹⁶·2³⁰, `|2w·(s −
    /// k)|` < 2³⁰·2¹⁷): the debug builds' check.
    fn exact_wide(&self, s: i32, c: i32, w: i32) -> i32 {
        let t = 2 * mul_wide(self.k, c) + w as i64 - 2 * mul_wide(w, s - self.k);
        if t < 0 {
            s - 1
        } else if t >= 2 * w as i64 {
            s + 1
        } else {
            s
        }
    }

    /// [`Self::screen`]'s estimate of `k + ⌊c·k/w + ½⌋` before [`Self::exact`] (`|c| <
    /// w·2ᵍ`; `n`, `r` as there).
    #[inline(always)]
    fn estimate(&self, c: i32, n: u32, r: i32) -> i32 {
        let cn = c << (n - self.g);
        self.k + ((mul_hi_estimate(cn, mul_hi_k(self.kh, r)) + self.bias) >> self.shift)
    }

    /// The screen coordinate of `c` at `w` (`0 < w < 2³⁰⁻ᵍ`, `n = lz(w) − 1`, `r` =
    /// [`recip_refined`] of `w·2ⁿ`): `k + ⌊c·k/w + ½⌋`, computed as
    /// `k + ⌊(⌊cₙ·kr/2³²⌋ + 2ˢʰ⁻³³)/2ˢʰ⁻³²⌋` ([`Self::estimate`]) with `cₙ = c·2ⁿ⁻ᵍ` (below `w·2ⁿ` <
    /// 2³¹ once `|c| < w·2ᵍ`) and `kr = ⌊k16·r/2¹⁶⌋ ≈ k16·2⁴⁵/(w·2ⁿ)`
    /// ([`mul_hi_k`]): the product is below 2⁶¹ and the rounding bias lies in the
    /// high word since `sh ≥ 34`. That estimate ([`mul_hi_estimate`]: up to 2 below
    /// the high word on ARMv6-M, up to 2⁻⁸ of a unit after the shift by `sh − 32 ≥ 9`)
    /// is off the exact quotient by less than 2⁻⁶ of a unit (the reciprocal's error
    /// is below 2⁻²⁶ of the quotient, which is below `k·2ᵍ` < 2¹⁹), so its rounding
    /// is within one of the exact one, and [`Self::exact`] gives the exact one on
    /// every core. `None` outside the guard band; with `CLAMP`, clamped into it
    /// instead.
    #[inline(always)]
    fn screen<const CLAMP: bool>(&self, c: i32, w: i32, n: u32, r: i32) -> Option<i32> {
        let lim = GUARD - 1;
        if c.unsigned_abs() >= (w << self.g) as u32 {
            return if CLAMP {
                Some(if c < 0 { -lim } else { lim })
            } else {
                None
            };
        }
        let s = self.exact(self.estimate(c, n, r), c, w);
        if s.unsigned_abs() >= GUARD as u32 {
            return if CLAMP {
                Some(s.clamp(-lim, lim))
            } else {
                None
            };
        }
        Some(s)
    }
}

/// The projection of one frame: clip coordinates in the frame's clip units to Q12.4
/// screen positions and Q16.16 depths, with one normalised reciprocal of w per
/// vertex ([`recip_refined`]) and 32-bit arithmetic (two `SMMUL` per axis on
/// ARMv7E-M; no 64-bit product on ARMv6-M but [`mul_hi`]'s).
///
/// The frame's clip units are `2^scale` per clip-space unit, one scale for every
/// object, chosen from how far any vertex can lie from the eye (`reach`) so that the
/// vertex stage's x and y stay below 2³⁰ and w below `2^w_bits` = 2³⁰⁻ᵍ, `g` the
/// larger guard exponent of the two axes (2ᵍ bounds |x/w| and |y/w| inside the
/// guard band). The transform's rounding ([`VertexTransform`](crate::math::VertexTransform):
/// integer entries) moves x, y and w by up to 3·2^(P−1−s) + 1.5 clip units, `P`
/// the position bits and `s` the entries' fraction bits (P = 17, s = 13 for a mesh
/// within ±2 units: 25.5 units; P = 19, s = 18 beyond: 4.5), and a clip unit of x
/// or y is `8·width/w` or `8·height/w` subpixels on screen (w in clip units). On
/// the tessellated ground plane of the effects table (`ground-fine`, 40 units
/// across) the screen positions differ from the f64 projection's by up to 0.002
/// subpixel at the far end and 0.02 near the eye, and each of its 406 visible
/// vertices rounds to the subpixel the exact position does.
///
/// Under a perspective projection w is the eye-space depth in clip units, the near
/// and far planes are two thresholds on w (exactly where the clipper's z from w,
/// [`ZFromW`], crosses ∓w) and the depth is taken from the same reciprocal,
/// `K·(1 − W_n/w)` (no z row, no z product); an orthographic projection takes the
/// depth `(1 + z/w)/2` from z.
///
/// ```
/// use fixshade::geometry::{Projector, Viewport};
/// use fixshade::math::Mat4;
/// // An orthographic identity on a 64×48 frame, vertices within 4 units of the eye.
/// let vp = Viewport { width: 64, height: 48 };
/// let p = Projector::new(vp, &Mat4::IDENTITY, None, 4 << 32).unwrap();
/// let one = 1i64 << p.scale();
/// // The clip-space origin lands on the frame's centre (Q12.4), at half depth
/// // (Q16.16 units of the u16 depth buffer).
/// let (x, y, z) = p.project_clip([0, 0, 0, one]).unwrap();
/// assert_eq!((x, y), (32 * 16, 24 * 16));
/// assert_eq!(z >> 16, 0x7FFF);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Projector {
    vp: Viewport,
    x: Axis,
    y: Axis,
    w_bits: u32,
    scale: i32,
    persp: Option<PerspectiveDepth>,
}

/// Perspective constants of a [`Projector`].
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct PerspectiveDepth {
    /// z from w for the clipper.
    z: ZFromW,
    /// Inside the depth range exactly for `w_lo ≤ w ≤ w_hi`, where w < 2^`w_bits`
    /// (`w_hi` capped there and at 2²⁸ times the near distance: the vertex stage
    /// leaves a vertex beyond to the clipper, which does not cut it).
    w_lo: i32,
    w_hi: i32,
    /// The depth `K·(1 − W_n/w)` as `(kd − (kz >> (jz − n)))·2ᵈ`: `kd = K/2ᵈ` in
    /// [2²⁷, 2²⁸), `kz = ⌊e31·r/2³²⌋ ≈ e31·2²⁹/(w·2ⁿ)` with `e31·2^(29 − jz + d) =
    /// K·W_n` (`e31` in [2³⁰, 2³¹)).
    kd: i32,
    d: u32,
    /// `DEPTH_SCALE >> d`: the clamp before the shift.
    dmax: i32,
    e31: i32,
    jz: u32,
}

impl PerspectiveDepth {
    /// See [`Projector::w_range`].
    pub(crate) fn w_range(&self) -> (i32, i32) {
        (self.w_lo, self.w_hi)
    }
}

/// The 64-bit depth scale as `i128` for the frame constants.
const DS: i128 = DEPTH_SCALE as i128;

/// Bit length of a non-negative `i128`.
fn bits128(v: i128) -> i32 {
    128 - v.unsigned_abs().leading_zeros() as i32
}

impl Projector {
    /// The projection for a `vp` frame under `proj` (a [`Mat4::perspective`] when
    /// `depth_range` gives its Q16.16 near and far distances, else a
    /// [`Mat4::orthographic`]), for vertices within `reach` (Q32.32) of the eye in
    /// every eye-space coordinate. `None` if the constants do not fit (a
    /// degenerate projection).
    pub fn new(
        vp: Viewport,
        proj: &Mat4,
        depth_range: Option<(Q16_16, Q16_16)>,
        reach: i64,
    ) -> Option<Projector> {
        let (x, y) = (Axis::new(vp.width), Axis::new(vp.height));
        let w_bits = 30 - x.g.max(y.g);
        // Bounds of the rows over the reach, Q64: (|P_r0| + |P_r1| + |P_r2|)·R + |P_r3|.
        // The reach is taken as at least twice the near distance, so the near plane
        // lies well inside w's range (a scene nearer than that is all behind it).
        let near = depth_range.map_or(0, |(n, _)| (n.to_bits().max(0) as i128) << 17);
        let reach = (reach.max(0) as i128).max(near);
        let mut scale = 48;
        for (r, row) in proj.m.iter().enumerate() {
            if r == 2 && depth_range.is_some() {
                continue; // z comes from w
            }
            let l: i128 = row[..3]
                .iter()
                .map(|v| v.unsigned_abs() as i128)
                .sum::<i128>()
                * reach
                + ((row[3].unsigned_abs() as i128) << 32);
            if l > 0 {
                let limit = if r == 3 { w_bits as i32 } else { 30 };
                // 2^scale·l < 2^(limit + 63) makes the row below half its limit.
                scale = scale.min(limit + 63 - bits128(l));
            }
        }
        let persp = match depth_range {
            None => None,
            Some((near, far)) => Some(Self::perspective(proj, scale, near, far, w_bits)?),
        };
        Some(Projector {
            vp,
            x,
            y,
            w_bits,
            scale,
            persp,
        })
    }

    /// The perspective constants (see [`PerspectiveDepth`]).
    fn perspective(
        proj: &Mat4,
        scale: i32,
        near: Q16_16,
        far: Q16_16,
        w_bits: u32,
    ) -> Option<PerspectiveDepth> {
        let (n, f) = (near.to_bits() as i128, far.to_bits() as i128);
        if n <= 0 || f <= n {
            return None;
        }
        // z = A·w + B: A = −P22 (Q32.32, above 1), B = P23 in clip units.
        let a_q = -(proj.m[2][2] as i128);
        let a = (a_q >> 32).clamp(1, i32::MAX as i128) as i32;
        let frac = ((a_q - ((a as i128) << 32)).clamp(0, (1 << 32) - 1) >> 2) as i32;
        let b = proj.m[2][3] as i128;
        let bz = if scale >= 32 {
            b << (scale - 32)
        } else {
            (b + (1i128 << (31 - scale))) >> (32 - scale)
        };
        let z = ZFromW {
            a,
            frac,
            bz: i64::try_from(bz).ok()?,
        };
        // Thresholds: the least w with z + w ≥ 0 and the greatest with z − w ≤ 0
        // (z + w and w − z are monotone in w: the slope is at least 1).
        let search = |inside: &dyn Fn(i32) -> bool, lowest: bool| -> i32 {
            let (mut lo, mut hi) = (1i64, i32::MAX as i64);
            if lowest {
                if !inside(i32::MAX) {
                    return i32::MAX;
                }
                while lo < hi {
                    let mid = (lo + hi) / 2;
                    if inside(mid as i32) {
                        hi = mid
                    } else {
                        lo = mid + 1
                    }
                }
                lo as i32
            } else {
                if !inside(1) {
                    return 0;
                }
                while lo < hi {
                    let mid = (lo + hi + 1) / 2;
                    if inside(mid as i32) {
                        lo = mid
                    } else {
                        hi = mid - 1
                    }
                }
                lo as i32
            }
        };
        let w_lo = search(&|w| z.z(w) + w as i64 >= 0, true);
        let w_hi = search(&|w| z.z(w) - w as i64 <= 0, false);
        // Depth constants from the exact near and far distances in clip units:
        // K = DS·f/(f − n), with 20 more fraction bits, and K·W_n.
        let k_q = ((DS * f) << 20) / (f - n);
        let k = k_q >> 20;
        let d = (bits128(k) - 28).max(0);
        let kd = ((k + ((1i128 << d) >> 1)) >> d) as i32;
        // K·W_n with W_n = n·2^(scale − 16): k_q·n·2^(scale − 36).
        let kn = k_q * n;
        let e = if scale >= 36 {
            kn << (scale - 36)
        } else {
            kn >> (36 - scale)
        };
        if e <= 0 {
            return None;
        }
        // E to 31 bits: e31 = E/2^ee in [2^30, 2^31).
        let mut ee = bits128(e) - 31;
        let mut e31 = (if ee >= 0 {
            (e + ((1i128 << ee) >> 1)) >> ee
        } else {
            e << -ee
        }) as i64;
        if e31 >= 1 << 31 {
            e31 >>= 1;
            ee += 1;
        }
        let jz = 29 - ee + d;
        // The shift jz − n must lie in 0..32: n ≤ jz holds from w_lo on (the
        // constants make it 1 to 3 there), and n ≥ jz − 31 below 2^(62 − jz). A
        // vertex beyond that (farther than 2^28 times the near distance) or beyond
        // the transform's range goes to the clipper instead.
        let w_lo = w_lo.max(1);
        let n_max = crate::math::leading_zeros(w_lo as u32) as i32 - 1;
        if jz < n_max || jz > 61 {
            return None;
        }
        let top = ((1i64 << (62 - jz).min(31)) - 1).min((1i64 << w_bits) - 1) as i32;
        Some(PerspectiveDepth {
            z,
            w_lo,
            w_hi: w_hi.min(top),
            kd,
            d: d as u32,
            dmax: (DEPTH_SCALE >> d) as i32,
            e31: e31 as i32,
            jz: jz as u32,
        })
    }

    /// A projector of no frame (0 × 0), as a constant placeholder.
    pub(crate) const UNSET: Projector = {
        const AXIS: Axis = Axis {
            k: 0,
            kh: 0,
            g: 0,
            shift: 0,
            bias: 0,
        };
        Projector {
            vp: Viewport {
                width: 0,
                height: 0,
            },
            x: AXIS,
            y: AXIS,
            w_bits: 0,
            scale: 0,
            persp: None,
        }
    };

    /// The frame.
    pub fn viewport(&self) -> &Viewport {
        &self.vp
    }

    /// Clip units per clip-space unit, as a power of two (for
    /// [`VertexTransform::new`](crate::math::VertexTransform::new)).
    pub fn scale(&self) -> i32 {
        self.scale
    }

    /// The vertex stage's w lies below `2^w_bits` (for [`VertexTransform::new`](crate::math::VertexTransform::new)).
    pub fn w_bits(&self) -> u32 {
        self.w_bits
    }

    /// The clipper's z from w under a perspective projection.
    pub fn z_from_w(&self) -> Option<ZFromW> {
        self.persp.map(|p| p.z)
    }

    /// The depth range in w under a perspective projection: a vertex with w in
    /// `[lo, hi]` lies between the near and far planes (and the vertex stage
    /// projects it; `hi` is capped below the far plane for a far plane beyond the
    /// scene's reach or 2²⁸ times the near distance).
    pub fn w_range(&self) -> Option<(i32, i32)> {
        self.persp.map(|p| p.w_range())
    }

    /// Q16.16 depth from the reciprocal of w (perspective): `(kd − q)·2ᵈ` clamped to
    /// [0, DEPTH_SCALE], `q = kz >> (jz − n)` (`kz` < 2³⁰, the shift in 0..32).
    #[inline(always)]
    fn depth_w(p: &PerspectiveDepth, n: u32, r: i32) -> u32 {
        let q = mul_hi(p.e31, r) >> (p.jz - n);
        ((p.kd - q).clamp(0, p.dmax) as u32) << p.d
    }

    /// Q16.16 depth from z (orthographic, `|z| ≤ w`): `DS/2 + ⌊z·2ⁿ·kz/2²⁹⌋` with
    /// `kz = ⌊32767·r/2¹⁶⌋ ≈ 32767·2⁴⁵/(w·2ⁿ)`; `|z·2ⁿ|` ≤ `w·2ⁿ` < 2³¹, the product
    /// below 2⁶¹.
    #[inline(always)]
    fn depth_z(z: i32, n: u32, r: i32) -> u32 {
        let q = mul_wide(z << n, mul_hi_k(32767 << 16, r)) >> 29;
        ((DEPTH_SCALE >> 1) + q).clamp(0, DEPTH_SCALE) as u32
    }

    /// The perspective constants, for [`Self::project_perspective`].
    pub(crate) fn perspective_depth(&self) -> Option<&PerspectiveDepth> {
        self.persp.as_ref()
    }

    /// The screen position and depth of a vertex of the vertex stage under a
    /// perspective projection (`depth` = [`Self::perspective_depth`]): `|x|, |y| <
    /// 2³⁰`, `w` within [`Self::w_range`] (and below `2^w_bits`). `None` outside the
    /// guard band. (As [`Axis::screen`] for both axes, with the tests gathered.)
    #[inline(always)]
    pub(crate) fn project_perspective(
        &self,
        depth: &PerspectiveDepth,
        x: i32,
        y: i32,
        w: i32,
    ) -> Option<(i32, i32, u32)> {
        let (ax, ay) = (&self.x, &self.y);
        if x.unsigned_abs() >= (w << ax.g) as u32 || y.unsigned_abs() >= (w << ay.g) as u32 {
            return None;
        }
        let n = leading_zeros(w as u32) - 1;
        let r = recip_refined((w as u32) << n);
        let (sx, sy) = (ax.estimate(x, n, r), ay.estimate(-y, n, r));
        let (sx, sy) = (ax.exact(sx, x, w), ay.exact(sy, -y, w));
        // Both inside exactly when the OR of their magnitudes is (a power of two).
        const _: () = assert!(GUARD.count_ones() == 1);
        if (sx.unsigned_abs() | sy.unsigned_abs()) >= GUARD as u32 {
            return None;
        }
        Some((sx, sy, Self::depth_w(depth, n, r)))
    }

    /// [`Self::project_perspective`] for an orthographic projection: `|x|, |y|, |z| <
    /// 2³⁰`, `0 < w < 2^w_bits`, `|z| ≤ w`.
    #[inline(always)]
    pub(crate) fn project_orthographic(
        &self,
        x: i32,
        y: i32,
        z: i32,
        w: i32,
    ) -> Option<(i32, i32, u32)> {
        let n = leading_zeros(w as u32) - 1;
        let r = recip_refined((w as u32) << n);
        let sx = self.x.screen::<false>(x, w, n, r)?;
        let sy = self.y.screen::<false>(-y, w, n, r)?;
        Some((sx, sy, Self::depth_z(z, n, r)))
    }

    /// Projects clip coordinates of any scale in the frame's clip units (the
    /// clipper's), clamping what rounding in the clipper may have pushed a hair
    /// outside: x and y into the guard band, the depth to [0, 1]. `None` only if
    /// `w ≤ 0`. For a vertex the vertex stage projected ([`VertexTransform::transform`](crate::math::VertexTransform::transform)
    /// of a vertex inside the guard band and the depth range) the result is the
    /// vertex stage's, bit for bit.
    pub fn project_clip(&self, c: [i64; 4]) -> Option<(i32, i32, u32)> {
        let [x, y, z, w] = c;
        if w <= 0 {
            return None;
        }
        // Shift right until x, y (and z without a perspective projection) are below
        // 2^30 and w below 2^w_bits: the ratios are kept, the exponent dropped.
        let zz = if self.persp.is_some() {
            0
        } else {
            z.unsigned_abs()
        };
        let big = x.unsigned_abs() | y.unsigned_abs() | zz;
        let s = (64 - big.leading_zeros() as i32 - 30)
            .max(64 - (w as u64).leading_zeros() as i32 - self.w_bits as i32)
            .max(0);
        let (xs, ys, zs, ws) = (
            (x >> s) as i32,
            (y >> s) as i32,
            (z >> s) as i32,
            ((w >> s) as i32).max(1),
        );
        let n = leading_zeros(ws as u32) - 1;
        let r = recip_refined((ws as u32) << n);
        let sx = self.x.screen::<true>(xs, ws, n, r)?;
        let sy = self.y.screen::<true>(-ys, ws, n, r)?;
        let sz = match &self.persp {
            Some(p) => {
                // The depth of w clamped into the depth range, in clip units.
                let wc = w.clamp(p.w_lo as i64, p.w_hi.max(p.w_lo) as i64) as i32;
                if s == 0 && wc == ws {
                    Self::depth_w(p, n, r)
                } else {
                    let nc = leading_zeros(wc as u32) - 1;
                    Self::depth_w(p, nc, recip_refined((wc as u32) << nc))
                }
            }
            None => Self::depth_z(zs.clamp(-ws, ws), n, r),
        };
        Some((sx, sy, sz))
    }
}

impl core::ops::Deref for Projector {
    type Target = Viewport;
    fn deref(&self) -> &Viewport {
        &self.vp
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

    /// The projector against exact rational projection: positions within one unit
    /// of the exact rounding, and equal to it unless the exact quotient lies within
    /// 2⁻⁸ of a half (the quotient's error is below 2⁻²⁶ of it, at most 2¹⁷ units in
    /// the guard band); None exactly outside the guard band (up to that rounding);
    /// the depth within 2⁻¹⁰ of a u16 step of `DS·(1/W_n − 1/w)/(1/W_n − 1/W_f)`.
    #[test]
    fn projector_matches_exact_projection() {
        use crate::fixed::Angle;
        let mut seed = 0x3141_5926_5358_9793u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let (mut differ, mut total, mut worst_depth) = (0u32, 0u32, 0f64);
        for case in 0..300 {
            let (width, height) = (1 + (next() % 4096) as u32, 1 + (next() % 4096) as u32);
            let vp = Viewport { width, height };
            let near = 1 + (next() % (4 << 16)) as i32;
            let far = near + 1 + (next() % ((1000 * near as u64).min(1 << 30))) as i32;
            let (near, far) = (Q16_16::from_bits(near), Q16_16::from_bits(far));
            let fovy = Angle::from_degrees(10 + (next() % 150) as i32);
            let proj = Mat4::perspective(fovy, width, height, near, far).unwrap();
            let reach = (far.to_bits() as i64) << (16 + case % 3);
            let Some(pr) = Projector::new(vp, &proj, Some((near, far)), reach) else {
                panic!("case {case}: no projector for near {near:?} far {far:?}");
            };
            let (w_lo, w_hi) = pr.w_range().unwrap();
            let w_top = w_hi.min((1 << pr.w_bits()) - 1);
            if w_lo > w_top {
                continue;
            }
            let wn = near.to_bits() as f64 * 2f64.powi(pr.scale() - 16);
            let wf = far.to_bits() as f64 * 2f64.powi(pr.scale() - 16);
            for _ in 0..2000 {
                let w = w_lo + (next() % (w_top - w_lo + 1) as u64) as i32;
                let spread = ((w as i64) << (next() % 16)).min((1 << 30) - 1);
                let c = |r: u64| ((r % (2 * spread as u64 + 1)) as i64 - spread) as i32;
                let (x, y) = (c(next()), c(next()));
                let got = pr.project_perspective(pr.perspective_depth().unwrap(), x, y, w);
                let exact = |k: i64, c: i32| -> (i128, bool) {
                    // k + round(k·c/w): floor((2kc + w)/(2w)), and whether near a half.
                    let n = 2 * k as i128 * c as i128 + w as i128;
                    let d = 2 * w as i128;
                    let q = n.div_euclid(d);
                    let rem = n.rem_euclid(d); // distance above the rounding point
                    let near_half = rem * 256 < d || (d - rem) * 256 < d;
                    (k as i128 + q, near_half)
                };
                let (ex, hx) = exact(8 * width as i64, x);
                let (ey, hy) = exact(8 * height as i64, -y);
                let g = GUARD as i128;
                let inside = ex.abs() < g && ey.abs() < g;
                let edge = ex.abs() == g || ey.abs() == g || ex.abs() == g - 1 || ey.abs() == g - 1;
                match got {
                    Some((sx, sy, sz)) => {
                        assert!(
                            inside || edge,
                            "case {case}: ({x}, {y}, {w}) outside, got {got:?}"
                        );
                        for (s, e, h) in [(sx, ex, hx), (sy, ey, hy)] {
                            assert!((s as i128 - e).abs() <= 1, "case {case}: {s} vs {e}");
                            if s as i128 != e {
                                assert!(h, "case {case}: {s} vs {e} not near a half");
                                differ += 1;
                            }
                            total += 1;
                        }
                        let want = DS as f64 * (1.0 / wn - 1.0 / w as f64) / (1.0 / wn - 1.0 / wf);
                        let want = want.clamp(0.0, DS as f64);
                        worst_depth = worst_depth.max((sz as f64 - want).abs() / 65536.0);
                    }
                    None => assert!(
                        !inside || edge,
                        "case {case}: ({x}, {y}, {w}) inside, got None"
                    ),
                }
            }
        }
        assert!(total > 100_000, "{total}");
        assert!(differ * 1000 < total, "{differ} of {total} differ");
        assert!(
            worst_depth < 1.0 / 1024.0,
            "depth off by {worst_depth} u16 steps"
        );
    }
}
