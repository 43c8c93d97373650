//! The draw calls of a prepared frame (`Frame::draw*`): each picks its shading
//! mode's fill ([`super::fills`]) and runs the triangle walk ([`super::walk`]) with
//! it. Above the frame, the walk and the fills, so none of them imports this.

use super::fills::{PerPixel, PerspectiveColours, QuadraticColours, VertexColours};
use super::frame::{Frame, RenderError, Stats};
use crate::divide::{Divide, Exact};
use crate::raster::perspective::Perspective;
use crate::raster::phong::{self, PhongFill, Sampling};
use crate::raster::span::{DepthMode, DepthTest, Gradient, NoDepth, SpanMethod};
use crate::scene::ShadingMode;
use crate::shade::{Adaptive, Flat, Gouraud, Phong, PhongEvenOdd, QuadraticSurface, Shading};
use crate::specular::Specular;
use crate::target::{PixelFormat, Target};

impl<'s, 'a, 'c, P: PixelFormat, Sp: Specular> Frame<'s, 'a, 'c, P, Sp> {
    /// Draws with the scene's depth and shading settings and the span method `S`.
    pub fn draw<S: SpanMethod, T: Target<P>>(&self, target: &mut T) -> Result<Stats, RenderError> {
        if self.scene.depth_test && !target.has_depth() {
            return Err(RenderError::NoDepthBuffer);
        }
        match (self.scene.depth_test, self.scene.shading) {
            (true, ShadingMode::Gouraud) => self.draw_with::<S, DepthTest, Gouraud, T>(target),
            (true, ShadingMode::Flat) => self.draw_with::<S, DepthTest, Flat, T>(target),
            (false, ShadingMode::Gouraud) => self.draw_with::<S, NoDepth, Gouraud, T>(target),
            (false, ShadingMode::Flat) => self.draw_with::<S, NoDepth, Flat, T>(target),
            (true, ShadingMode::QuadraticSurface) => {
                self.draw_with::<S, DepthTest, QuadraticSurface, T>(target)
            }
            (false, ShadingMode::QuadraticSurface) => {
                self.draw_with::<S, NoDepth, QuadraticSurface, T>(target)
            }
            (true, ShadingMode::Phong) => self.draw_with::<S, DepthTest, Phong, T>(target),
            (false, ShadingMode::Phong) => self.draw_with::<S, NoDepth, Phong, T>(target),
            (true, ShadingMode::PhongEvenOdd) => {
                self.draw_with::<S, DepthTest, PhongEvenOdd, T>(target)
            }
            (false, ShadingMode::PhongEvenOdd) => {
                self.draw_with::<S, NoDepth, PhongEvenOdd, T>(target)
            }
            (true, ShadingMode::Adaptive) => {
                self.draw_with::<S, DepthTest, crate::shade::Adaptive, T>(target)
            }
            (false, ShadingMode::Adaptive) => {
                self.draw_with::<S, NoDepth, crate::shade::Adaptive, T>(target)
            }
        }
    }

    /// Draws with every variant chosen by type: span method, depth mode, shading.
    ///
    /// Quadratic ([`Shading::QUADRATIC`]), Phong ([`Shading::PER_PIXEL`]) and
    /// adaptive shading have their own fills and take from `S` only its
    /// [`SpanMethod::Divider`] (for their setup's reciprocal); their coverage is that
    /// of [`Gradient`].
    pub fn draw_with<S: SpanMethod, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if Sh::ADAPTIVE {
            return self.draw_adaptive::<S::Divider, Z, T>(target, None);
        }
        if Sh::QUADRATIC {
            return self.draw_quadratic::<S::Divider, Z, Sh, T>(target);
        }
        if Sh::PER_PIXEL {
            return if Sh::EVEN_ODD {
                self.draw_phong::<S::Divider, Z, phong::EvenOddPixels, T>(target, None, None)
            } else {
                self.draw_phong::<S::Divider, Z, phong::Rows, T>(target, None, None)
            };
        }
        let rows = target.rows();
        self.walk(rows, &mut VertexColours::<T, S, Z, Sh>::new(target))
    }

    /// Phong shading with the lighting sampled by pixel segments (seed 002 §2.6, see
    /// [`Sampling`]): the same coverage and depth as [`Frame::draw_with`] with
    /// [`crate::shade::Phong`], and with `segment = 1` the same pixels; larger
    /// segments light fewer pixels ([`Stats::evaluations`]) and interpolate the
    /// rest where the segment ends differ by at most the threshold. The depth test
    /// follows the scene.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::raster::phong::Sampling;
    /// use fixshade::sampler::{Threshold, SEED_K_Q8};
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb888>::prepare(&scene, 64, 64, &mut cache).unwrap();
    /// let (mut px, mut z) = ([[0u8; 3]; 64 * 64], [0xFFFFu16; 64 * 64]);
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, Some(&mut z), 64, 64).unwrap();
    /// let k = Threshold::from_q8(SEED_K_Q8, [255; 3]);
    /// let st = frame.draw_phong_sampled(&mut fb, Sampling { segment: 8, threshold: k }).unwrap();
    /// assert!(st.evaluations < st.pixels); // fewer lighting evaluations than pixels
    /// ```
    pub fn draw_phong_sampled<T: Target<P>>(
        &self,
        target: &mut T,
        sampling: Sampling,
    ) -> Result<Stats, RenderError> {
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if self.scene.depth_test && !target.has_depth() {
            return Err(RenderError::NoDepthBuffer);
        }
        if self.scene.depth_test {
            self.draw_phong::<Exact, DepthTest, phong::Rows, T>(target, Some(sampling), None)
        } else {
            self.draw_phong::<Exact, NoDepth, phong::Rows, T>(target, Some(sampling), None)
        }
    }

    /// The quadratic path of [`Frame::draw_with`].
    fn draw_quadratic<D: Divide, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        let rows = target.rows();
        self.walk(rows, &mut QuadraticColours::<T, D, Z, Sh>::new(target))
    }

    /// The Phong path of [`Frame::draw_with`]: eye-space normals and positions from
    /// the mesh (see [`Frame`]), every covered pixel lit with this frame's
    /// [`crate::light::LightingSetup`]. Clipped triangles carry normal and position through the
    /// clipper as six attributes, so they are Phong-shaded too. With `persp` the
    /// attributes are perspective-correct (unless `sampling` is given).
    fn draw_phong<D: Divide, Z: DepthMode, F: PhongFill, T: Target<P>>(
        &self,
        target: &mut T,
        sampling: Option<Sampling>,
        persp: Option<Perspective>,
    ) -> Result<Stats, RenderError> {
        let rows = target.rows();
        let mut fill = PerPixel::<T, D, Z, F>::new(target, sampling, persp);
        self.walk(rows, &mut fill)
    }

    /// Draws with perspective-correct Gouraud colours (see [`crate::raster::perspective`]): the
    /// colour is sampled with one reciprocal through `D` at every pixel or at the
    /// ends of sub-spans (`mode`), and interpolated linearly in between; coverage and
    /// depth are those of [`Frame::draw`] with [`Gradient`]. The depth test follows
    /// the scene.
    ///
    /// Phong shading interpolates its normals and eye positions perspective-correctly
    /// ([`crate::raster::perspective::draw_phong_perspective`]; the even/odd fill
    /// draws as the one-accumulator fill does), and adaptive shading draws its
    /// Gouraud triangles and its per-pixel ones each through its perspective fill.
    /// Flat shading needs no correction, and the quadratic surface draws as
    /// [`Frame::draw`] draws it (its surface interpolates in screen space).
    ///
    /// ```
    /// use fixshade::divide::Exact;
    /// use fixshade::prelude::*;
    /// use fixshade::raster::perspective::Perspective;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb888>::prepare(&scene, 64, 64, &mut cache).unwrap();
    /// let (mut px, mut z) = ([[0u8; 3]; 64 * 64], [0xFFFFu16; 64 * 64]);
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, Some(&mut z), 64, 64).unwrap();
    /// let st = frame.draw_perspective::<Exact, _>(&mut fb, Perspective::SUB16).unwrap();
    /// assert!(st.pixels > 0);
    /// ```
    pub fn draw_perspective<D: Divide, T: Target<P>>(
        &self,
        target: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        use ShadingMode as M;
        let shading = self.scene.shading;
        if !matches!(
            shading,
            M::Gouraud | M::Phong | M::PhongEvenOdd | M::Adaptive
        ) {
            return self.draw::<Gradient, T>(target);
        }
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if self.scene.depth_test && !target.has_depth() {
            return Err(RenderError::NoDepthBuffer);
        }
        // Even/odd Phong draws with the one-accumulator fill (the same pixels).
        match (shading, self.scene.depth_test) {
            (M::Gouraud, true) => {
                self.draw_perspective_as::<D, DepthTest, Gouraud, T>(target, mode)
            }
            (M::Gouraud, false) => self.draw_perspective_as::<D, NoDepth, Gouraud, T>(target, mode),
            (M::Adaptive, true) => {
                self.draw_perspective_as::<D, DepthTest, Adaptive, T>(target, mode)
            }
            (M::Adaptive, false) => {
                self.draw_perspective_as::<D, NoDepth, Adaptive, T>(target, mode)
            }
            (_, true) => self.draw_perspective_as::<D, DepthTest, Phong, T>(target, mode),
            (_, false) => self.draw_perspective_as::<D, NoDepth, Phong, T>(target, mode),
        }
    }

    /// [`Frame::draw_perspective`] with the depth mode and the shading fixed by type,
    /// as [`Frame::draw_with`] fixes them: only that combination's code is linked (a
    /// Gouraud-only firmware carries no Phong fill). Flat and quadratic shading draw
    /// as [`Frame::draw_with`] with [`Gradient`] draws them.
    ///
    /// ```
    /// use fixshade::divide::Exact;
    /// use fixshade::prelude::*;
    /// use fixshade::raster::perspective::Perspective;
    /// use fixshade::raster::span::DepthTest;
    /// use fixshade::shade::Gouraud;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb888>::prepare(&scene, 64, 64, &mut cache).unwrap();
    /// let (mut px, mut z) = ([[0u8; 3]; 64 * 64], [0xFFFFu16; 64 * 64]);
    /// let mut fb = Framebuffer::<Rgb888>::new(&mut px, Some(&mut z), 64, 64).unwrap();
    /// let st = frame
    ///     .draw_perspective_as::<Exact, DepthTest, Gouraud, _>(&mut fb, Perspective::SUB16)
    ///     .unwrap();
    /// assert!(st.pixels > 0);
    /// ```
    pub fn draw_perspective_as<D: Divide, Z: DepthMode, Sh: Shading, T: Target<P>>(
        &self,
        target: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        if !Sh::INTERPOLATE || Sh::QUADRATIC {
            return self.draw_with::<Gradient, Z, Sh, T>(target);
        }
        if target.width() != self.vp.width || target.frame_height() != self.vp.height {
            return Err(RenderError::TargetSizeMismatch);
        }
        if Sh::ADAPTIVE {
            return self.draw_adaptive::<D, Z, T>(target, Some(mode));
        }
        if Sh::PER_PIXEL {
            return self.draw_phong::<D, Z, phong::Rows, T>(target, None, Some(mode));
        }
        self.draw_perspective_with::<D, Z, T>(target, mode)
    }

    /// The perspective-correct Gouraud path of [`Frame::draw_perspective_as`].
    fn draw_perspective_with<D: Divide, Z: DepthMode, T: Target<P>>(
        &self,
        target: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        let rows = target.rows();
        self.walk(rows, &mut PerspectiveColours::<T, D, Z>::new(target, mode))
    }
}
