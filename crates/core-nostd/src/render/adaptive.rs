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

use super::frame::{
    classify, clip_w, eye_normal, project_clamped, Class, Frame, RenderError, Stats,
};
use crate::clip::{clip_triangle, is_front, ClipVertex};
use crate::divide::Divide;
use crate::light::{LightingSetup, Specular};
use crate::math::Affine3;
use crate::raster::draw_triangle;
use crate::raster::perspective::{draw_phong_perspective, draw_triangle_perspective, Perspective};
use crate::raster::phong::{draw_phong_div, PhongVertex, Rows};
use crate::raster::span::{DepthMode, Gradient, WithDivide};
use crate::shade::Gouraud;
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
        if Sp::TWO_SIDED {
            return Err(RenderError::TwoSidedUnsupported);
        }
        // One Phong triangle with its clip-space w.
        let phong =
            |target: &mut T, v: [PhongVertex; 3], w: [i64; 3], light: &LightingSetup<Sp>| {
                match persp {
                    Some(m) => draw_phong_perspective::<P, T, Z, D, _>(target, v, w, m, light),
                    None => draw_phong_div::<P, T, Z, Rows, D, _>(target, v, light),
                }
            };
        let view = self.scene.camera.view().ok_or(RenderError::BadView)?;
        let mut st = Stats::default();
        let cull = self.scene.cull_back;
        let rows = target.rows();
        let limit = half_step::<P>();
        for (i, (obj, prep)) in self.prepared().enumerate() {
            let mv = view.mul(&obj.placement.matrix());
            let aff = Affine3::new(&mv).ok_or(RenderError::SingularModel { object: i })?;
            let light: LightingSetup<Sp> = self.lighting(obj, &view);
            let verts = &self.cache[prep.offset..prep.offset + obj.mesh.positions().len()];
            let (pos, nrm) = (obj.mesh.positions(), obj.mesh.normals());
            let eye = |i: usize| -> ([i32; 3], [i32; 3]) {
                (eye_normal(&aff, &nrm[i]), aff.point(&pos[i]))
            };
            for tri in obj.mesh.triangles() {
                st.triangles += 1;
                let t = tri.map(|i| verts[i as usize]);
                let class = classify(&t, cull, &self.vp, rows.clone());
                if let Class::Skip(why) = class {
                    st.skip(why);
                    continue;
                }
                let e: [([i32; 3], [i32; 3]); 3] = core::array::from_fn(|k| eye(tri[k] as usize));
                if class == Class::Draw {
                    let n = e.map(|v| v.0);
                    let p = e.map(|v| v.1);
                    st.drawn += 1;
                    let w = clip_w(persp, prep.clip(), pos, *tri);
                    // Twice the area in Q12.4² (256 per pixel): |·| < 2⁶³ for
                    // coordinates within ±2²⁰ (the guard band is far inside).
                    let area2 = crate::clip::signed_area(
                        (t[0].s.x, t[0].s.y),
                        (t[1].s.x, t[1].s.y),
                        (t[2].s.x, t[2].s.y),
                    )
                    .abs();
                    if area2 >= 2 * 256 * PHONG_BELOW_PIXELS
                        && light.within_bounds(&n, &p, limit, DIFFUSE_STEPS * 2 * limit)
                    {
                        let s = [t[0].s, t[1].s, t[2].s];
                        st.pixels += match persp {
                            Some(m) => {
                                draw_triangle_perspective::<P, T, Z, Gouraud, D>(target, s, w, m)
                            }
                            None => draw_triangle::<P, T, WithDivide<Gradient, D>, Z, Gouraud>(
                                target, s,
                            ),
                        };
                    } else {
                        st.per_pixel += 1;
                        let pv = core::array::from_fn(|k| {
                            let s = t[k].s;
                            PhongVertex {
                                x: s.x,
                                y: s.y,
                                z: s.z,
                                n: e[k].0,
                                p: e[k].1,
                            }
                        });
                        st.pixels += phong(target, pv, w, &light);
                    }
                    continue;
                }
                // Through the clipper: Phong, as `draw_phong` does.
                st.clipped += 1;
                st.per_pixel += 1;
                let cv: [ClipVertex<6>; 3] = core::array::from_fn(|k| {
                    let (n, p) = e[k];
                    ClipVertex {
                        pos: prep.clip().transform(&pos[tri[k] as usize]),
                        c: [n[0], n[1], n[2], p[0], p[1], p[2]],
                    }
                });
                let poly = clip_triangle(cv, &self.vp);
                let mut pv = [PhongVertex::default(); crate::clip::MAX_POLY];
                let mut pw = [1i64; crate::clip::MAX_POLY];
                for ((o, ow), v) in pv
                    .iter_mut()
                    .zip(pw.iter_mut())
                    .zip(poly.v[..poly.len].iter())
                {
                    let Some((x, y, z)) = project_clamped(&self.vp, v.pos) else {
                        continue;
                    };
                    *ow = v.pos[3];
                    let c = v.c;
                    *o = PhongVertex {
                        x,
                        y,
                        z,
                        n: [c[0], c[1], c[2]],
                        p: [c[3], c[4], c[5]],
                    };
                }
                for k in 1..poly.len.saturating_sub(1) {
                    let tri = [pv[0], pv[k], pv[k + 1]];
                    let pts = tri.map(|v| (v.x, v.y));
                    let area = crate::clip::signed_area(pts[0], pts[1], pts[2]);
                    if area == 0 || (cull && !is_front(pts[0], pts[1], pts[2])) {
                        continue;
                    }
                    st.drawn += 1;
                    st.pixels += phong(target, tri, [pw[0], pw[k], pw[k + 1]], &light);
                }
            }
        }
        Ok(st)
    }
}

#[cfg(test)]
mod tests {
    use crate::prelude::*;
    use crate::raster::span::DepthTest;
    use crate::renderer::rgb;
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
