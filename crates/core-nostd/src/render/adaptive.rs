//! Adaptive shading ([`crate::shade::Adaptive`]): per triangle, Phong where a
//! highlight can reach inside it, Gouraud elsewhere.
//!
//! The highlight test is conservative: [`LightingSetup::specular_bound`] bounds the
//! specular term over the whole triangle (every normal Phong could interpolate there,
//! every point of it), and a triangle where it reaches half a step of the target's
//! finest channel is lit per pixel, so no highlight is lost. Gouraud's error in the
//! ambient and diffuse light is bounded too ([`LightingSetup::diffuse_bound`], how
//! far the interpolated light can be from the per-pixel one): a triangle where that
//! bound reaches [`DIFFUSE_STEPS`] steps is lit per pixel as well. Both bounds share
//! one cone of the vertex normals. Triangles of fewer than [`PHONG_BELOW_PIXELS`]
//! pixels are lit per pixel without the bounds (cheaper there). Gouraud triangles take the vertex colours lit by
//! the vertex stage; triangles that go through the clipper are always Phong-shaded.
//! With perspective correction each kind of triangle goes through its perspective
//! fill ([`crate::raster::perspective`]); the choice between them is the same.

use core::marker::PhantomData;

use super::fills::{persp_w, Lit};
use super::frame::{Frame, RenderError, Stats};
use super::walk::{Triangle, TriangleFill};
use crate::divide::Divide;
use crate::light::LightingSetup;
use crate::raster::draw_triangle;
use crate::raster::perspective::{draw_phong_perspective, draw_triangle_perspective, Perspective};
use crate::raster::phong::{draw_phong_div, PhongVertex, Rows};
use crate::raster::span::{DepthMode, Gradient, WithDivide};
use crate::shade::Gouraud;
use crate::specular::Specular;
use crate::target::{PixelFormat, Target};

/// Steps of the finest channel by which Gouraud's ambient and diffuse light may
/// differ from the per-pixel light (by [`LightingSetup::diffuse_bound`], a loose
/// bound) on a triangle drawn with Gouraud. The seed's check bounds the highlight
/// alone; 8 keeps NMSE against full Phong below 1e-4 on the three figures while
/// most triangles take Gouraud (docs/effects.md). Measured on the teapot, the
/// figure nearest the limit, with the earlier terminator bound (a directional
/// light's whole `max N·L` on any triangle its terminator crossed): NMSE 8.3e-6
/// with ½ step (1 280 of 1 741 triangles per pixel, 1.24× Phong's time), 6.4e-5
/// with 8 (748, about 1×), 9.9e-5 with 16, 1.4e-4 with no diffuse bound (516,
/// 0.86×). With the present bound (how far the vertices lie behind the
/// terminator) and 8: 8.8e-5, 603 triangles, 0.89–0.91×.
const DIFFUSE_STEPS: i64 = 8;

/// Triangles covering fewer pixels than this (by area) are lit per pixel without
/// evaluating the bounds: on them the bounds cost more than Phong's pixels (about
/// 200 ns a triangle on the host against tens of ns a Phong pixel; the
/// `figures-adaptive` scene, about 2 pixels a triangle, took 1.2× Phong's time with
/// every triangle bounded). Phong is the conservative choice, so no highlight is
/// lost.
const PHONG_BELOW_PIXELS: i64 = 4;

/// Half a step of the finest channel of `P`, Q16.16: the largest specular light a
/// Gouraud triangle may leave out.
fn half_step<P: PixelFormat>() -> i64 {
    let m = P::MAX[0].max(P::MAX[1]).max(P::MAX[2]).max(1) as i64;
    (1i64 << 16) / (2 * m)
}

impl<P: PixelFormat, Sp: Specular> Frame<'_, '_, '_, P, Sp> {
    /// The adaptive path of [`Frame::draw_with`], perspective-correct with `persp`
    /// ([`Frame::draw_perspective`]).
    pub(super) fn draw_adaptive<D: Divide, Z: DepthMode, T: Target<P>>(
        &self,
        target: &mut T,
        persp: Option<Perspective>,
    ) -> Result<Stats, RenderError> {
        if Sp::two_sided() {
            return Err(RenderError::TwoSidedUnsupported);
        }
        let rows = target.rows();
        let mut fill = AdaptiveFill::<T, D, Z> {
            target,
            persp,
            limit: half_step::<P>(),
            _kind: PhantomData,
        };
        self.walk(rows, &mut fill)
    }
}

/// Adaptive shading's fill for the triangle walk: Gouraud or Phong per triangle
/// inside the guard band (see the [module docs](self)), Phong through the clipper,
/// with the divider `D` and the depth mode `Z`; perspective-correct with `persp`.
struct AdaptiveFill<'t, T, D, Z> {
    target: &'t mut T,
    persp: Option<Perspective>,
    /// [`half_step`] of the target's format.
    limit: i64,
    _kind: PhantomData<(D, Z)>,
}

impl<T, D: Divide, Z: DepthMode> AdaptiveFill<'_, T, D, Z> {
    /// One Phong triangle with its clip-space w.
    #[inline(always)]
    fn phong<P: PixelFormat, Sp: Specular>(
        &mut self,
        v: [PhongVertex; 3],
        w: [i64; 3],
        light: &LightingSetup<Sp>,
    ) -> u32
    where
        T: Target<P>,
    {
        match self.persp {
            Some(m) => draw_phong_perspective::<P, T, Z, D, _>(self.target, v, w, m, light),
            None => draw_phong_div::<P, T, Z, Rows, D, _>(self.target, v, light),
        }
    }
}

impl<P: PixelFormat, Sp: Specular, T: Target<P>, D: Divide, Z: DepthMode> TriangleFill<P, Sp>
    for AdaptiveFill<'_, T, D, Z>
{
    type PerObject = Lit<Sp>;

    #[inline(always)]
    fn inside(&mut self, lit: &Lit<Sp>, tri: &Triangle<'_, '_>, st: &mut Stats) -> u32 {
        let pv = lit.phong_vertices(tri, false);
        let n = [pv[0].n, pv[1].n, pv[2].n];
        let p = [pv[0].p, pv[1].p, pv[2].p];
        let w = persp_w(self.persp, tri);
        let t = tri.screen();
        // Twice the area in Q12.4² (256 per pixel): |·| < 2⁶³ for coordinates
        // within ±2²⁰ (the guard band is far inside).
        let area2 =
            crate::clip::signed_area((t[0].x, t[0].y), (t[1].x, t[1].y), (t[2].x, t[2].y)).abs();
        let limit = self.limit;
        if area2 >= 2 * 256 * PHONG_BELOW_PIXELS
            && lit
                .light
                .within_bounds(&n, &p, limit, DIFFUSE_STEPS * 2 * limit)
        {
            let s = [*t[0], *t[1], *t[2]];
            match self.persp {
                Some(m) => draw_triangle_perspective::<P, T, Z, Gouraud, D>(self.target, s, w, m),
                None => draw_triangle::<P, T, WithDivide<Gradient, D>, Z, Gouraud>(self.target, s),
            }
        } else {
            st.per_pixel += 1;
            self.phong::<P, Sp>(pv, w, &lit.light)
        }
    }

    /// Through the clipper: Phong, as [`Frame::draw_with`] draws it.
    #[inline(always)]
    fn clipped(&mut self, lit: &Lit<Sp>, tri: &Triangle<'_, '_>, st: &mut Stats) {
        st.per_pixel += 1;
        lit.clip_phong(tri, st, |v, w, light| self.phong::<P, Sp>(v, w, light));
    }
}

#[cfg(test)]
mod tests {
    use crate::light::rgb;
    use crate::prelude::*;
    use crate::raster::span::DepthTest;
    use crate::shade::Adaptive;

    /// `(drawn, per_pixel)` of the documentation's triangle with no specular colour
    /// (no highlight anywhere, equal normals: both bounds are 0) in a `size`² frame.
    fn counts(size: u32) -> (u32, u32) {
        let mut scene = crate::doc_support::scene();
        let m = &mut scene.objects[0].material;
        *m = m.with_specular(rgb(0, 0, 0), 32);
        let mut cache = [XfVertex::default(); 3];
        let frame = Frame::<Rgb888>::prepare(&scene, size, size, &mut cache).unwrap();
        let n = (size * size) as usize;
        let (mut px, mut z) = ([[0u8; 3]; 32 * 32], [0xFFFFu16; 32 * 32]);
        let mut fb = Framebuffer::new(&mut px[..n], Some(&mut z[..n]), size, size).unwrap();
        let st = frame
            .draw_with::<Gradient, DepthTest, Adaptive, _>(&mut fb)
            .unwrap();
        (st.drawn, st.per_pixel)
    }

    #[test]
    fn tiny_triangles_skip_the_bounds_and_pay() {
        // About 170 pixels: the bounds say Gouraud.
        assert_eq!(counts(32), (1, 0));
        // About 1.5 pixels (below PHONG_BELOW_PIXELS): Phong without the bounds.
        assert_eq!(counts(3), (1, 1));
    }
}
