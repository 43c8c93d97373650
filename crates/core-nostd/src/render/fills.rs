//! The shading modes' fills for the triangle walk ([`super::walk`]): each says how
//! a triangle inside the guard band is set up and filled and how a clipped one is,
//! and nothing else (the walk iterates, classifies, culls and counts).
//!
//! - [`VertexColours`]: Gouraud and flat shading with any span method, from the
//!   vertex stage's colours ([`super::Frame::draw_with`]);
//! - [`PerspectiveColours`]: Gouraud with perspective-correct colours
//!   ([`super::Frame::draw_perspective`]);
//! - [`QuadraticColours`]: the quadratic surface through lit edge midpoints;
//! - [`PerPixel`]: Phong shading (sampled and perspective-correct too);
//! - adaptive shading's fill is in [`super::adaptive`], the binning's in
//!   [`super::bands`].

use crate::arrays;
use core::marker::PhantomData;

use super::frame::{eye_normal, Frame, RenderError, Stats};
use super::walk::{ObjectSetup, Triangle, TriangleFill};
use crate::divide::Divide;
use crate::fixed::Q16_16;
use crate::geometry::Mesh;
use crate::light::LightingSetup;
use crate::math::{normalize_to_q30, Affine3, Vec3};
use crate::raster::perspective::{draw_phong_perspective, draw_triangle_perspective, Perspective};
use crate::raster::phong::{draw_phong_div, draw_phong_sampled, PhongFill, PhongVertex, Sampling};
use crate::raster::quadratic::draw_quadratic_div;
use crate::raster::span::{DepthMode, Gradient, SpanMethod, WithDivide};
use crate::raster::{draw_in_guard, draw_triangle, ScreenVertex};
use crate::scene::Object;
use crate::shade::{Gouraud, Shading};
use crate::specular::Specular;
use crate::target::{to_channels, PixelFormat, Target};

/// Gouraud or flat shading (`Sh`) with the span method `S` and the depth mode `Z`:
/// the vertex stage's colours (the back colours on a back face under two-sided
/// lighting; flat shading takes the last vertex's colour).
pub(super) struct VertexColours<'t, T, S, Z, Sh> {
    target: &'t mut T,
    _kind: PhantomData<(S, Z, Sh)>,
}

impl<'t, T, S, Z, Sh> VertexColours<'t, T, S, Z, Sh> {
    /// The fill drawing into `target`.
    pub(super) fn new(target: &'t mut T) -> Self {
        VertexColours {
            target,
            _kind: PhantomData,
        }
    }
}

impl<P: PixelFormat, Sp: Specular, T: Target<P>, S: SpanMethod, Z: DepthMode, Sh: Shading>
    TriangleFill<P, Sp> for VertexColours<'_, T, S, Z, Sh>
{
    type PerObject = ();
    const SNAPS: bool = S::SNAPS;

    #[inline(always)]
    fn snap(v: ScreenVertex) -> ScreenVertex {
        S::snap(v)
    }

    /// Snapped vertices are tested against the guard band again, since snapping
    /// moves them.
    #[inline(always)]
    fn inside(&mut self, _: &(), tri: &Triangle<'_, '_>, _: &mut Stats) -> u32 {
        let back = tri.faces_back::<Sp>();
        if S::SNAPS {
            draw_triangle::<P, T, S, Z, Sh>(self.target, tri.coloured(Sh::INTERPOLATE, back))
        } else if Sh::INTERPOLATE && !back {
            // The cached vertices as they are: no copy.
            draw_in_guard::<P, T, S, Z, Sh>(self.target, tri.screen())
        } else {
            let s = tri.coloured(Sh::INTERPOLATE, back);
            draw_in_guard::<P, T, S, Z, Sh>(self.target, [&s[0], &s[1], &s[2]])
        }
    }

    /// Not inlined: the walk of every span method stays small (the clipper is
    /// rare, and the micro:bit images are near their flash).
    #[inline(never)]
    fn clipped(&mut self, _: &(), tri: &Triangle<'_, '_>, st: &mut Stats) {
        let target = &mut *self.target;
        tri.clip_coloured::<Sp>(Sh::INTERPOLATE, st, |s, _| {
            draw_triangle::<P, T, S, Z, Sh>(target, s)
        });
    }
}

/// Perspective-correct Gouraud colours ([`crate::raster::perspective`]) through
/// the divider `D`, with the depth mode `Z`.
pub(super) struct PerspectiveColours<'t, T, D, Z> {
    target: &'t mut T,
    mode: Perspective,
    _kind: PhantomData<(D, Z)>,
}

impl<'t, T, D, Z> PerspectiveColours<'t, T, D, Z> {
    /// The fill drawing into `target` in `mode`.
    pub(super) fn new(target: &'t mut T, mode: Perspective) -> Self {
        PerspectiveColours {
            target,
            mode,
            _kind: PhantomData,
        }
    }
}

impl<P: PixelFormat, Sp: Specular, T: Target<P>, D: Divide, Z: DepthMode> TriangleFill<P, Sp>
    for PerspectiveColours<'_, T, D, Z>
{
    type PerObject = ();

    #[inline(always)]
    fn inside(&mut self, _: &(), tri: &Triangle<'_, '_>, _: &mut Stats) -> u32 {
        let s = tri.coloured(true, tri.faces_back::<Sp>());
        let w = tri.clip_w();
        draw_triangle_perspective::<P, T, Z, Gouraud, D>(self.target, s, w, self.mode)
    }

    #[inline(always)]
    fn clipped(&mut self, _: &(), tri: &Triangle<'_, '_>, st: &mut Stats) {
        let (target, mode) = (&mut *self.target, self.mode);
        tri.clip_coloured::<Sp>(true, st, |s, w| {
            draw_triangle_perspective::<P, T, Z, Gouraud, D>(target, s, w, mode)
        });
    }
}

/// What the fills that light at draw time keep per object (see [`Frame`]): the
/// model-view [`Affine3`] and the lighting setups.
pub(super) struct Lit<Sp: Specular> {
    /// The object's model-view map.
    pub(super) aff: Affine3,
    /// The lighting setup of the front faces.
    pub(super) light: LightingSetup<Sp>,
    /// Under two-sided lighting, the back faces' (the back material's).
    back: Option<LightingSetup<Sp>>,
}

/// Object `index`'s lighting under the frame's view, with the back faces' setup
/// under two-sided lighting.
impl<P: PixelFormat, Sp: Specular> ObjectSetup<P, Sp> for Lit<Sp> {
    fn new(
        frame: &Frame<'_, '_, '_, P, Sp>,
        index: usize,
        obj: &Object<'_>,
    ) -> Result<Self, RenderError> {
        let view = frame.view();
        let mv = view.mul(&obj.placement.matrix());
        let aff = Affine3::new(&mv).ok_or(RenderError::SingularModel { object: index })?;
        let light = frame.lighting(obj, view);
        let back = if Sp::two_sided() {
            Some(frame.back_lighting(obj, view))
        } else {
            None
        };
        Ok(Lit { aff, light, back })
    }
}

impl<Sp: Specular> Lit<Sp> {
    /// The setup lighting a face and the sign of its normals: the back setup and
    /// −1 for a back face under two-sided lighting (the interpolated normal
    /// negated: the vertex normals negated, Q2.30 components within ±2³⁰, no
    /// overflow; the fill renormalises).
    #[inline(always)]
    pub(super) fn facing(&self, back: bool) -> (&LightingSetup<Sp>, i32) {
        match (&self.back, back) {
            (Some(b), true) => (b, -1),
            _ => (&self.light, 1),
        }
    }

    /// Eye-space unit normal and position of vertex `i` of `mesh`.
    #[inline(always)]
    fn eye(&self, mesh: &Mesh<'_>, i: u16) -> ([i32; 3], [i32; 3]) {
        let i = i as usize;
        (
            eye_normal(&self.aff, &mesh.normals()[i]),
            self.aff.point(&mesh.positions()[i]),
        )
    }

    /// The Phong vertices of a triangle inside the guard band, the normals negated
    /// on a `back` face (see [`Lit::facing`]).
    #[inline(always)]
    pub(super) fn phong_vertices(&self, tri: &Triangle<'_, '_>, back: bool) -> [PhongVertex; 3] {
        let sign = self.facing(back).1;
        // Not `core::array::from_fn`: the Cortex-M4 build keeps that out of line
        // (about 170 instructions a triangle more, measured on the report's sphere).
        let vertex = |k: usize| {
            let (n, p) = self.eye(&tri.obj.mesh, tri.idx[k]);
            let s = &tri.v[k].s;
            PhongVertex {
                x: s.x,
                y: s.y,
                z: s.z,
                n: if Sp::two_sided() {
                    arrays::map(n, |c| sign * c)
                } else {
                    n
                },
                p,
            }
        };
        [vertex(0), vertex(1), vertex(2)]
    }

    /// Clips a triangle carrying eye-space normals and positions (six attributes),
    /// and hands each piece of the fan to `draw` with the setup of its facing and
    /// its normals negated on a back face (see [`Lit::facing`]).
    #[inline(always)]
    pub(super) fn clip_phong(
        &self,
        tri: &Triangle<'_, '_>,
        st: &mut Stats,
        mut draw: impl FnMut([PhongVertex; 3], [i64; 3], &LightingSetup<Sp>) -> u32,
    ) {
        let cv = tri.clip_vertices(|k| {
            let (n, p) = self.eye(&tri.obj.mesh, tri.idx[k]);
            [n[0], n[1], n[2], p[0], p[1], p[2]]
        });
        let vertex = |(x, y, z), c: &[i32; 6], front: bool| {
            let n = [c[0], c[1], c[2]];
            PhongVertex {
                x,
                y,
                z,
                n: if Sp::two_sided() {
                    arrays::map(n, |c| self.facing(!front).1 * c)
                } else {
                    n
                },
                p: [c[3], c[4], c[5]],
            }
        };
        tri.clip_fan_with(cv, st, vertex, |v, w, front| {
            draw(v, w, self.facing(Sp::two_sided() && !front).0)
        });
    }

    /// The colour lit at the midpoint of the edge from mesh vertex `a` (colour
    /// `ca`) to `b` (colour `cb`), with the back setup and the negated normal on a
    /// `back` face; the average of the colours where the normals are opposite.
    #[inline(always)]
    fn midpoint<P: PixelFormat>(
        &self,
        mesh: &Mesh<'_>,
        (a, b): (usize, usize),
        (ca, cb): ([i32; 3], [i32; 3]),
        back: bool,
    ) -> [i32; 3] {
        let (pos, nrm, nm) = (mesh.positions(), mesh.normals(), &self.aff.normal);
        let m: Vec3 = arrays::from_fn(|k| {
            Q16_16::from_bits(
                ((pos[a][k].to_bits() as i64 + pos[b][k].to_bits() as i64) >> 1) as i32,
            )
        });
        let n: [i64; 3] =
            arrays::from_fn(|k| nrm[a][k].to_bits() as i64 + nrm[b][k].to_bits() as i64);
        // Entries < 2^31, components < 2^16: sums of three < 2^49.
        let ne: [i64; 3] = arrays::from_fn(|r| {
            nm[r][0] as i64 * n[0] + nm[r][1] as i64 * n[1] + nm[r][2] as i64 * n[2]
        });
        match normalize_to_q30(ne) {
            Some(unit) => {
                let at = self.aff.point(&m);
                to_channels::<P>(match (&self.back, back) {
                    // Q2.30 components within ±2³⁰: the negation cannot overflow.
                    (Some(b), true) => b.shade(at, arrays::map(unit, |c| -c)),
                    _ => self.light.shade(at, unit),
                })
            }
            // Opposite normals: no midpoint normal, average the colours.
            None => arrays::from_fn(|k| ((ca[k] as i64 + cb[k] as i64) >> 1) as i32),
        }
    }
}

/// The quadratic surface ([`crate::raster::quadratic`]) through the vertex colours
/// and the colours lit at the edge midpoints, with the divider `D`, the depth mode
/// `Z` and `Sh`'s fill. Two-sided lighting: back faces take the back colours at
/// the vertices and light their midpoints with the negated normal and the back
/// material. Clipped triangles are drawn with Gouraud ([`Stats::fallback`]: their
/// pieces have no midpoint colours).
pub(super) struct QuadraticColours<'t, T, D, Z, Sh> {
    target: &'t mut T,
    _kind: PhantomData<(D, Z, Sh)>,
}

impl<'t, T, D, Z, Sh> QuadraticColours<'t, T, D, Z, Sh> {
    /// The fill drawing into `target`.
    pub(super) fn new(target: &'t mut T) -> Self {
        QuadraticColours {
            target,
            _kind: PhantomData,
        }
    }
}

impl<P: PixelFormat, Sp: Specular, T: Target<P>, D: Divide, Z: DepthMode, Sh: Shading>
    TriangleFill<P, Sp> for QuadraticColours<'_, T, D, Z, Sh>
{
    type PerObject = Lit<Sp>;

    /// Out of line: inlined into the walk, the three midpoints' lighting costs the
    /// Cortex-M4 about 190 more instructions a triangle (register pressure in the
    /// loop; measured on the report's sphere).
    #[inline(never)]
    fn inside(&mut self, lit: &Lit<Sp>, tri: &Triangle<'_, '_>, _: &mut Stats) -> u32 {
        let back = tri.faces_back::<Sp>();
        let s = tri.coloured(true, back);
        let m = arrays::from_fn(|k| {
            let (a, b) = (k, (k + 1) % 3);
            let ends = (tri.idx[a] as usize, tri.idx[b] as usize);
            lit.midpoint::<P>(&tri.obj.mesh, ends, (s[a].c, s[b].c), back)
        });
        draw_quadratic_div::<P, T, Z, D>(self.target, s, m, Sh::FILL)
    }

    #[inline(always)]
    fn clipped(&mut self, _: &Lit<Sp>, tri: &Triangle<'_, '_>, st: &mut Stats) {
        st.fallback += 1;
        let target = &mut *self.target;
        tri.clip_coloured::<Sp>(true, st, |s, _| {
            draw_triangle::<P, T, WithDivide<Gradient, D>, Z, Gouraud>(target, s)
        });
    }
}

/// Phong shading: every covered pixel lit with the object's [`LightingSetup`],
/// from eye-space normals and positions (see [`Frame`]); clipped triangles carry
/// them through the clipper, so they are Phong-shaded too. The divider `D`, the
/// depth mode `Z`, the span fill `F`; lighting sampled by segments with
/// `sampling`, else perspective-correct with `persp`.
pub(super) struct PerPixel<'t, T, D, Z, F> {
    target: &'t mut T,
    sampling: Option<Sampling>,
    persp: Option<Perspective>,
    _kind: PhantomData<(D, Z, F)>,
}

impl<'t, T, D, Z, F> PerPixel<'t, T, D, Z, F> {
    /// The fill drawing into `target`.
    pub(super) fn new(
        target: &'t mut T,
        sampling: Option<Sampling>,
        persp: Option<Perspective>,
    ) -> Self {
        PerPixel {
            target,
            sampling,
            persp,
            _kind: PhantomData,
        }
    }
}

/// The clip-space w of `tri` when `persp` asks for perspective correction; else
/// unused, `[1; 3]`.
#[inline(always)]
pub(super) fn persp_w(persp: Option<Perspective>, tri: &Triangle<'_, '_>) -> [i64; 3] {
    match persp {
        Some(_) => tri.clip_w(),
        None => [1; 3],
    }
}

impl<T, D, Z, F> PerPixel<'_, T, D, Z, F> {
    /// One Phong triangle with its clip-space w: (pixels covered, evaluations).
    #[inline(always)]
    fn draw<P, Sp>(
        &mut self,
        v: [PhongVertex; 3],
        w: [i64; 3],
        light: &LightingSetup<Sp>,
    ) -> (u32, u32)
    where
        P: PixelFormat,
        Sp: Specular,
        T: Target<P>,
        D: Divide,
        Z: DepthMode,
        F: PhongFill,
    {
        match (self.sampling, self.persp) {
            (Some(sm), _) => draw_phong_sampled::<P, T, Z, _>(self.target, v, light, sm),
            (None, Some(m)) => (
                draw_phong_perspective::<P, T, Z, D, _>(self.target, v, w, m, light),
                0,
            ),
            (None, None) => (draw_phong_div::<P, T, Z, F, D, _>(self.target, v, light), 0),
        }
    }
}

impl<P: PixelFormat, Sp: Specular, T: Target<P>, D: Divide, Z: DepthMode, F: PhongFill>
    TriangleFill<P, Sp> for PerPixel<'_, T, D, Z, F>
{
    type PerObject = Lit<Sp>;

    #[inline(always)]
    fn inside(&mut self, lit: &Lit<Sp>, tri: &Triangle<'_, '_>, st: &mut Stats) -> u32 {
        let back = tri.faces_back::<Sp>();
        let pv = lit.phong_vertices(tri, back);
        let w = persp_w(self.persp, tri);
        let (px, ev) = self.draw::<P, Sp>(pv, w, lit.facing(back).0);
        st.evaluations += ev;
        px
    }

    #[inline(always)]
    fn clipped(&mut self, lit: &Lit<Sp>, tri: &Triangle<'_, '_>, st: &mut Stats) {
        let mut ev = 0;
        lit.clip_phong(tri, st, |v, w, light| {
            let (px, e) = self.draw::<P, Sp>(v, w, light);
            ev += e;
            px
        });
        st.evaluations += ev;
    }
}
