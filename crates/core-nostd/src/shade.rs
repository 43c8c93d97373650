//! Shading modes: what a triangle's colour does across its pixels.
//!
//! [`Flat`] gives the whole triangle the colour of its last (provoking) vertex, as
//! OpenGL does; [`Gouraud`] interpolates the vertex colours linearly in screen space.
//! [`QuadraticSurface`] fits a quadratic intensity surface through the vertex colours and
//! the colours lit at the edge midpoints (seed 003), filled in 2×2 blocks;
//! [`QuadraticSurfaceRows`] is the same surface filled row by row (bit-identical).
//! [`Phong`] and [`PhongEvenOdd`] light every pixel from interpolated normals.
//! The choice is a type, so the span loop of a flat triangle carries no colour
//! interpolation at all.

pub use crate::raster::shading::Shading;

/// One colour per triangle: its provoking (last) vertex's.
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::shade::Flat;
/// # let scene = fixshade::doc_support::scene();
/// let mut px = [0u16; 16 * 16];
/// let mut z = [0xFFFFu16; 16 * 16];
/// let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, Some(&mut z), 16, 16).unwrap();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::prepare(&scene, 16, 16, &mut cache).unwrap();
/// frame.draw_with::<Gradient, DepthTest, Flat, _>(&mut fb).unwrap();
/// // One colour over the whole triangle.
/// let lit: Vec<u16> = fb.color().iter().copied().filter(|&p| p != 0).collect();
/// assert!(lit.len() > 20 && lit.iter().all(|&p| p == lit[0]));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Flat;

/// Vertex colours interpolated linearly in screen space.
///
/// ```
/// use fixshade::shade::{Gouraud, Shading};
/// // The default of a scene: vertex colours interpolated with a constant increment.
/// assert!(Gouraud::INTERPOLATE && !Gouraud::QUADRATIC && !Gouraud::PER_PIXEL);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Gouraud;

impl Shading for Flat {
    const NAME: &'static str = "flat";
    const INTERPOLATE: bool = false;
}

impl Shading for Gouraud {
    const NAME: &'static str = "gouraud";
    const INTERPOLATE: bool = true;
}

/// The quadratic intensity surface (seed 003), 2×2 block fill over two scanlines.
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::shade::{QuadraticSurface, QuadraticSurfaceRows};
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::prepare(&scene, 24, 24, &mut cache).unwrap();
/// let draw = |first: bool| {
///     let (mut px, mut z) = ([0u8; 24 * 24], [0xFFFFu16; 24 * 24]);
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, Some(&mut z), 24, 24).unwrap();
///     if first {
///         frame.draw_with::<Gradient, DepthTest, QuadraticSurface, _>(&mut fb).unwrap();
///     } else {
///         frame.draw_with::<Gradient, DepthTest, QuadraticSurfaceRows, _>(&mut fb).unwrap();
///     }
///     px
/// };
/// // The two fills give the same pixels.
/// assert_eq!(draw(true), draw(false));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct QuadraticSurface;

/// The quadratic intensity surface filled row by row (same pixels as [`QuadraticSurface`]).
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::shade::{QuadraticSurfaceRows, QuadraticSurface};
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::prepare(&scene, 24, 24, &mut cache).unwrap();
/// let draw = |first: bool| {
///     let (mut px, mut z) = ([0u8; 24 * 24], [0xFFFFu16; 24 * 24]);
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, Some(&mut z), 24, 24).unwrap();
///     if first {
///         frame.draw_with::<Gradient, DepthTest, QuadraticSurfaceRows, _>(&mut fb).unwrap();
///     } else {
///         frame.draw_with::<Gradient, DepthTest, QuadraticSurface, _>(&mut fb).unwrap();
///     }
///     px
/// };
/// // The two fills give the same pixels.
/// assert_eq!(draw(true), draw(false));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct QuadraticSurfaceRows;

impl Shading for QuadraticSurface {
    const NAME: &'static str = "quadratic";
    const INTERPOLATE: bool = true;
    const QUADRATIC: bool = true;
    const FILL: crate::raster::quadratic::Fill = crate::raster::quadratic::Fill::Blocks;
}

impl Shading for QuadraticSurfaceRows {
    const NAME: &'static str = "quadratic-rows";
    const INTERPOLATE: bool = true;
    const QUADRATIC: bool = true;
    const FILL: crate::raster::quadratic::Fill = crate::raster::quadratic::Fill::Rows;
}

/// Phong shading: normals and eye positions interpolated, every pixel lit.
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::shade::{Phong, PhongEvenOdd};
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::prepare(&scene, 24, 24, &mut cache).unwrap();
/// let draw = |first: bool| {
///     let (mut px, mut z) = ([0u8; 24 * 24], [0xFFFFu16; 24 * 24]);
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, Some(&mut z), 24, 24).unwrap();
///     if first {
///         frame.draw_with::<Gradient, DepthTest, Phong, _>(&mut fb).unwrap();
///     } else {
///         frame.draw_with::<Gradient, DepthTest, PhongEvenOdd, _>(&mut fb).unwrap();
///     }
///     px
/// };
/// // The two fills give the same pixels.
/// assert_eq!(draw(true), draw(false));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Phong;

/// Phong shading with the even/odd fill of seed 003 (same pixels as [`Phong`]).
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::shade::{PhongEvenOdd, Phong};
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::prepare(&scene, 24, 24, &mut cache).unwrap();
/// let draw = |first: bool| {
///     let (mut px, mut z) = ([0u8; 24 * 24], [0xFFFFu16; 24 * 24]);
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, Some(&mut z), 24, 24).unwrap();
///     if first {
///         frame.draw_with::<Gradient, DepthTest, PhongEvenOdd, _>(&mut fb).unwrap();
///     } else {
///         frame.draw_with::<Gradient, DepthTest, Phong, _>(&mut fb).unwrap();
///     }
///     px
/// };
/// // The two fills give the same pixels.
/// assert_eq!(draw(true), draw(false));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct PhongEvenOdd;

impl Shading for Phong {
    const NAME: &'static str = "phong";
    const INTERPOLATE: bool = true;
    const PER_PIXEL: bool = true;
}

impl Shading for PhongEvenOdd {
    const NAME: &'static str = "phong-even-odd";
    const INTERPOLATE: bool = true;
    const PER_PIXEL: bool = true;
    const EVEN_ODD: bool = true;
}

/// Adaptive shading (the "inner specular check" of seed 002): per triangle, a
/// conservative bound of the specular term over the triangle
/// ([`crate::light::LightingSetup::specular_bound`]) decides whether a highlight can
/// reach inside it; those triangles are Phong-shaded, the rest Gouraud-shaded
/// (a bound of the diffuse error sends more to Phong; triangles under 4 pixels and
/// clipped triangles are always Phong-shaded).
/// [`crate::render::Stats::per_pixel`] counts the triangles that paid.
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::shade::Adaptive;
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb888>::prepare(&scene, 32, 32, &mut cache).unwrap();
/// let (mut px, mut z) = ([[0u8; 3]; 32 * 32], [0xFFFFu16; 32 * 32]);
/// let mut fb = Framebuffer::new(&mut px, Some(&mut z), 32, 32).unwrap();
/// let st = frame.draw_with::<Gradient, DepthTest, Adaptive, _>(&mut fb).unwrap();
/// // The light sits at the eye: the highlight is on the triangle, which pays per pixel.
/// assert_eq!((st.drawn, st.per_pixel), (1, 1));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Adaptive;

impl Shading for Adaptive {
    const NAME: &'static str = "adaptive";
    const INTERPOLATE: bool = true;
    const ADAPTIVE: bool = true;
}
