//! Clip & cull: homogeneous clipping against the near and far planes and the guard
//! band, and back-face culling.
//!
//! Most triangles never come here: a triangle whose three vertices project inside the
//! guard band (±4096 pixels) and the depth range is rasterized directly. The rest are
//! clipped as polygons (Sutherland–Hodgman) in clip space against six planes: near
//! (`z ≥ −w`), far (`z ≤ w`), and the four guard-band planes pulled in by one pixel so
//! the projected, rounded vertices stay inside. Colours are interpolated linearly in
//! the clip parameter, as OpenGL does.
//!
//! Bounds: the three vertices are shifted together so every |coordinate| < 2⁴⁰
//! (relative precision 2⁻³⁹); plane distances have coefficients below 2¹⁶ and stay
//! below 2⁵⁸, and the interpolation products `(b − a)·d` below 2⁹⁹ fit `i128`.

use crate::geometry::Viewport;
use crate::math::mul_wide;
use crate::raster::GUARD;

/// A polygon vertex: clip coordinates and `N` attributes interpolated with it: the
/// colour (target units, Q.16) for Gouraud, or normal and eye position for Phong.
///
/// ```
/// use fixshade::clip::ClipVertex;
/// // Clip position (x, y, z, w) and an RGB colour in target units, Q.16.
/// let v = ClipVertex { pos: [0, 0, 0, 1 << 20], c: [255 << 16, 0, 0] };
/// assert_eq!(ClipVertex::<3>::default().pos, [0; 4]);
/// assert_eq!(v.c[0] >> 16, 255);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct ClipVertex<const N: usize = 3> {
    /// Homogeneous coordinates x, y, z, w.
    pub pos: [i64; 4],
    /// Attributes (colour channels by default).
    pub c: [i32; N],
}

impl<const N: usize> Default for ClipVertex<N> {
    fn default() -> Self {
        ClipVertex {
            pos: [0; 4],
            c: [0; N],
        }
    }
}

/// Largest number of vertices a triangle clipped by six planes can have.
pub const MAX_POLY: usize = 9;

/// A clipped convex polygon.
///
/// ```
/// use fixshade::clip::{clip_triangle, ClipVertex, Polygon};
/// use fixshade::geometry::Viewport;
/// let w = 1 << 20;
/// let v = |x, y| ClipVertex { pos: [x, y, 0, w], c: [0; 3] };
/// let p: Polygon = clip_triangle([v(0, 0), v(w / 2, 0), v(0, w / 2)], &Viewport { width: 64, height: 64 });
/// assert_eq!(p.len, 3); // inside: unchanged
/// assert_eq!(p.v[1].pos, [w / 2, 0, 0, w]);
/// ```
#[derive(Copy, Clone, Debug)]
pub struct Polygon<const N: usize = 3> {
    /// Vertices; the first `len` are valid.
    pub v: [ClipVertex<N>; MAX_POLY],
    /// Number of vertices.
    pub len: usize,
}

/// Signed distance to plane `k` (≥ 0 inside) for the viewport's guard band.
#[inline]
fn distance(k: usize, p: &[i64; 4], vp: &Viewport) -> i128 {
    let [x, y, z, w] = p.map(|v| v as i128);
    let g = (GUARD - 16) as i128;
    let sw = 8 * vp.width as i128;
    let sh = 8 * vp.height as i128;
    match k {
        0 => z + w,
        1 => w - z,
        // 8W(x + w)/w > −g and < g; 8H(w − y)/w likewise.
        2 => sw * (x + w) + g * w,
        3 => g * w - sw * (x + w),
        4 => sh * (w - y) + g * w,
        _ => g * w - sh * (w - y),
    }
}

/// Clips triangle `t` to the view volume and guard band. The result has 0 or 3..=9
/// vertices.
///
/// ```
/// use fixshade::clip::{clip_triangle, ClipVertex};
/// use fixshade::geometry::Viewport;
/// let w = 1 << 20;
/// let v = |z: i64| ClipVertex { pos: [0, 0, z, w], c: [0; 3] };
/// let vp = Viewport { width: 64, height: 64 };
/// // A triangle crossing the near plane z = -w loses its tip: two vertices were cut in.
/// let mut t = [v(0), v(-2 * w), v(0)];
/// t[1].pos[0] = w / 2;
/// t[2].pos[1] = w / 2;
/// let p = clip_triangle(t, &vp);
/// assert_eq!(p.len, 4);
/// assert!(p.v[..p.len].iter().all(|c| c.pos[2] >= -c.pos[3]));
/// // Entirely behind the near plane: nothing is left.
/// assert_eq!(clip_triangle([v(-2 * w); 3], &vp).len, 0);
/// ```
pub fn clip_triangle<const N: usize>(t: [ClipVertex<N>; 3], vp: &Viewport) -> Polygon<N> {
    // Common shift so every coordinate is below 2^40.
    let max = t
        .iter()
        .flat_map(|v| v.pos.iter())
        .fold(0u64, |m, c| m | c.unsigned_abs());
    let shift = (64 - max.leading_zeros() as i32 - 40).max(0);
    let mut cur = Polygon {
        v: [ClipVertex::default(); MAX_POLY],
        len: 3,
    };
    for (i, v) in t.iter().enumerate() {
        cur.v[i] = ClipVertex {
            pos: v.pos.map(|c| c >> shift),
            c: v.c,
        };
    }
    for k in 0..6 {
        if cur.len == 0 {
            break;
        }
        let mut next = Polygon {
            v: [ClipVertex::default(); MAX_POLY],
            len: 0,
        };
        for i in 0..cur.len {
            let a = cur.v[i];
            let b = cur.v[(i + 1) % cur.len];
            let (da, db) = (distance(k, &a.pos, vp), distance(k, &b.pos, vp));
            if da >= 0 {
                push(&mut next, a);
            }
            if (da >= 0) != (db >= 0) {
                push(&mut next, intersect(&a, &b, da, db));
            }
        }
        cur = next;
    }
    if cur.len < 3 {
        cur.len = 0;
    }
    cur
}

fn push<const N: usize>(p: &mut Polygon<N>, v: ClipVertex<N>) {
    // A convex polygon gains at most one vertex per plane: 3 + 6 = MAX_POLY.
    if p.len < MAX_POLY {
        p.v[p.len] = v;
        p.len += 1;
    }
}

/// The point where the segment a→b crosses the plane: `a + (b − a)·da/(da − db)`,
/// computed from the endpoint with the smaller position whichever way the segment is
/// walked: two polygons sharing a mesh edge walk it in opposite directions, and the
/// truncating division would otherwise give them points one unit apart — after the
/// projection, a crack of one pixel between their fans.
fn intersect<const N: usize>(
    a: &ClipVertex<N>,
    b: &ClipVertex<N>,
    da: i128,
    db: i128,
) -> ClipVertex<N> {
    if b.pos < a.pos {
        return intersect(b, a, db, da);
    }
    let den = da - db; // non-zero: the signs differ
    let lerp = |x: i128, y: i128| x + (y - x) * da / den;
    ClipVertex {
        pos: core::array::from_fn(|i| lerp(a.pos[i] as i128, b.pos[i] as i128) as i64),
        c: core::array::from_fn(|i| lerp(a.c[i] as i128, b.c[i] as i128) as i32),
    }
}

/// True if the screen triangle faces the viewer: counter-clockwise as seen, which with
/// y pointing down means a negative signed area. Zero-area triangles are not front
/// faces (they are dropped anyway).
///
/// ```
/// use fixshade::clip::is_front;
/// // y points down: counter-clockwise as seen on screen is a front face.
/// assert!(is_front((0, 0), (0, 16), (16, 0)));
/// assert!(!is_front((0, 0), (16, 0), (0, 16)));
/// ```
#[inline]
pub fn is_front(a: (i32, i32), b: (i32, i32), c: (i32, i32)) -> bool {
    signed_area(a, b, c) < 0
}

/// Twice the signed area of a Q12.4 screen triangle (y down). |coordinates| < 2¹⁶
/// (the guard band), so each product is below 2³⁴: `i64`.
///
/// ```
/// use fixshade::clip::signed_area;
/// // Twice the area of a 1×1-pixel right triangle in Q12.4 (16 units per pixel).
/// assert_eq!(signed_area((0, 0), (16, 0), (0, 16)), 256);
/// ```
///
/// The deltas are `i32` (wrapping: coordinates outside ±2³⁰ give a meaningless
/// area, never a panic) and the products [`crate::math::mul_wide`]. On ARMv6-M,
/// where that is four 16-bit products, deltas below 2¹⁵ in magnitude (a triangle
/// under 2048 pixels across) take two 32-bit products instead: each below 2³⁰,
/// their difference below 2³¹, the same value.
#[inline]
pub fn signed_area(a: (i32, i32), b: (i32, i32), c: (i32, i32)) -> i64 {
    let (dx1, dy1) = (b.0.wrapping_sub(a.0), b.1.wrapping_sub(a.1));
    let (dx2, dy2) = (c.0.wrapping_sub(a.0), c.1.wrapping_sub(a.1));
    #[cfg(fixshade_v6m)]
    if (dx1.unsigned_abs() | dy1.unsigned_abs() | dx2.unsigned_abs() | dy2.unsigned_abs()) < 1 << 15
    {
        return (dx1 * dy2 - dx2 * dy1) as i64;
    }
    mul_wide(dx1, dy2) - mul_wide(dx2, dy1)
}

/// [`signed_area`] with 32-bit products, for |coordinates| < 2²⁹ (the deltas and
/// `delta + 2¹⁵` fit `i32`) and when every edge delta lies in [−2¹⁵, 2¹⁵) (a triangle under 2048
/// pixels across): each product then lies in
/// [−2³⁰ + 2¹⁵, 2³⁰] and their difference strictly inside ±2³¹, so the `i32` value
/// is exact. `None` for larger deltas. ARMv6-M has no 32×32→64-bit multiply; this
/// takes two `MULS` where [`signed_area`] takes two `__aeabi_lmul` calls.
///
/// ```
/// use fixshade::clip::{signed_area, signed_area_i32};
/// assert_eq!(signed_area_i32((0, 0), (16, 0), (0, 16)), Some(256));
/// assert_eq!(signed_area_i32((0, 0), (1 << 15, 0), (0, 16)), None);
/// let (a, b, c) = ((-16384, 3), (16383, -16384), (5, 16383));
/// assert_eq!(signed_area_i32(a, b, c).map(i64::from), Some(signed_area(a, b, c)));
/// ```
#[inline(always)]
pub fn signed_area_i32(a: (i32, i32), b: (i32, i32), c: (i32, i32)) -> Option<i32> {
    crate::math::cross_small(b.0 - a.0, b.1 - a.1, c.0 - a.0, c.1 - a.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: i64, y: i64, z: i64, w: i64) -> ClipVertex {
        ClipVertex {
            pos: [x, y, z, w],
            c: [0; 3],
        }
    }

    /// A segment cut by a plane gives the same point walked either way (neighbouring
    /// polygons walk their shared edge in opposite directions).
    #[test]
    fn cut_point_does_not_depend_on_direction() {
        let vp = Viewport {
            width: 320,
            height: 240,
        };
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |m: i64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % (2 * m as u64)) as i64 - m
        };
        let mut cuts = 0;
        for _ in 0..20_000 {
            let p = |n: &mut dyn FnMut(i64) -> i64| {
                let w = n(1 << 20).abs() + 1;
                ClipVertex::<3> {
                    pos: [n(1 << 26), n(1 << 26), n(1 << 21), w],
                    c: [n(1 << 20) as i32, n(1 << 20) as i32, n(1 << 20) as i32],
                }
            };
            let (a, b) = (p(&mut next), p(&mut next));
            for k in 0..6 {
                let (da, db) = (distance(k, &a.pos, &vp), distance(k, &b.pos, &vp));
                if (da >= 0) != (db >= 0) {
                    cuts += 1;
                    let (ab, ba) = (intersect(&a, &b, da, db), intersect(&b, &a, db, da));
                    assert_eq!((ab.pos, ab.c), (ba.pos, ba.c));
                }
            }
        }
        assert!(cuts > 10_000, "{cuts}");
    }

    #[test]
    fn inside_triangle_is_unchanged() {
        let vp = Viewport {
            width: 100,
            height: 100,
        };
        let t = [
            v(0, 0, 0, 1 << 20),
            v(1 << 19, 0, 0, 1 << 20),
            v(0, 1 << 19, 0, 1 << 20),
        ];
        let p = clip_triangle(t, &vp);
        assert_eq!(p.len, 3);
        assert_eq!(p.v[1].pos, t[1].pos);
    }

    #[test]
    fn near_plane_cuts_a_corner() {
        let vp = Viewport {
            width: 100,
            height: 100,
        };
        // One vertex behind the near plane (z < -w).
        let one = 1 << 20;
        let t = [
            v(0, 0, 0, one),
            v(one / 2, 0, 0, one),
            v(0, 0, -2 * one, one),
        ];
        let p = clip_triangle(t, &vp);
        assert_eq!(p.len, 4);
        for q in &p.v[..p.len] {
            assert!(q.pos[2] + q.pos[3] >= 0);
        }
    }

    #[test]
    fn fully_outside_is_empty() {
        let vp = Viewport {
            width: 100,
            height: 100,
        };
        let one = 1 << 20;
        let t = [
            v(0, 0, 2 * one, one),
            v(one, 0, 2 * one, one),
            v(0, one, 3 * one, one),
        ];
        assert_eq!(clip_triangle(t, &vp).len, 0);
    }

    /// The 32-bit area equals the 64-bit one wherever it answers, and answers
    /// exactly when every delta lies in [−2¹⁵, 2¹⁵).
    #[test]
    fn small_area_equals_signed_area() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let edges = [-(1 << 15) - 1, -(1 << 15), -1, 0, 1, (1 << 15) - 1, 1 << 15];
        for &d1 in &edges {
            for &d2 in &edges {
                for &d3 in &edges {
                    let (a, b, c) = ((7, -3), (7 + d1, -3 + d2), (7 + d3, -3 + d1));
                    let small = [d1, d2, d3]
                        .iter()
                        .all(|d| (-(1 << 15)..1 << 15).contains(d));
                    let got = signed_area_i32(a, b, c);
                    assert_eq!(got.is_some(), small, "{d1} {d2} {d3}");
                    if let Some(s) = got {
                        assert_eq!(s as i64, signed_area(a, b, c));
                    }
                }
            }
        }
        for k in 0..1_000_000u32 {
            let r = next();
            let range = 1i64 << (8 + k % 22); // up to 2^29
            let c = |s: u32| ((r >> s) as i64 % range) as i32;
            let (a, b, cc) = ((c(0), c(5)), (c(10), c(15)), (c(20), c(25)));
            if let Some(s) = signed_area_i32(a, b, cc) {
                assert_eq!(s as i64, signed_area(a, b, cc), "{a:?} {b:?} {cc:?}");
            }
        }
    }
}
