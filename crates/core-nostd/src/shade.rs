//! Shading modes: what a triangle's colour does across its pixels.
//!
//! [`Flat`] gives the whole triangle the colour of its last (provoking) vertex, as
//! OpenGL does; [`Gouraud`] interpolates the vertex colours linearly in screen space.
//! [`Quadratic`] fits a quadratic intensity surface through the vertex colours and
//! the colours lit at the edge midpoints (seed 003), filled in 2×2 blocks;
//! [`QuadraticRows`] is the same surface filled row by row (bit-identical).
//! [`Phong`] and [`PhongEvenOdd`] light every pixel from interpolated normals.
//! The choice is a type, so the span loop of a flat triangle carries no colour
//! interpolation at all.

/// A shading mode.
pub trait Shading {
    /// Name used by the CLI and scene files.
    const NAME: &'static str;
    /// True if colours are interpolated across the triangle.
    const INTERPOLATE: bool;
    /// True for the quadratic intensity surface: [`crate::render::Frame`] lights
    /// the edge midpoints and fills with [`crate::raster::quadratic`]. A bare
    /// [`crate::raster::draw_triangle`] has no midpoint colours and treats it as
    /// Gouraud.
    const QUADRATIC: bool = false;
    /// How the quadratic surface is filled (only read when `QUADRATIC`).
    const FILL: crate::raster::quadratic::Fill = crate::raster::quadratic::Fill::Blocks;
    /// True for Phong shading: [`crate::render::Frame`] interpolates normals and
    /// eye positions and lights every pixel ([`crate::raster::phong`]).
    const PER_PIXEL: bool = false;
    /// With `PER_PIXEL`: the even/odd fill (two accumulators per attribute).
    const EVEN_ODD: bool = false;
    /// True for adaptive shading: [`crate::render::Frame`] decides per triangle
    /// between Phong and Gouraud ([`Adaptive`]).
    const ADAPTIVE: bool = false;
}

/// One colour per triangle: its provoking (last) vertex's.
#[derive(Copy, Clone, Debug, Default)]
pub struct Flat;

/// Vertex colours interpolated linearly in screen space.
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
#[derive(Copy, Clone, Debug, Default)]
pub struct Quadratic;

/// The quadratic intensity surface filled row by row (same pixels as [`Quadratic`]).
#[derive(Copy, Clone, Debug, Default)]
pub struct QuadraticRows;

impl Shading for Quadratic {
    const NAME: &'static str = "quadratic";
    const INTERPOLATE: bool = true;
    const QUADRATIC: bool = true;
    const FILL: crate::raster::quadratic::Fill = crate::raster::quadratic::Fill::Blocks;
}

impl Shading for QuadraticRows {
    const NAME: &'static str = "quadratic-rows";
    const INTERPOLATE: bool = true;
    const QUADRATIC: bool = true;
    const FILL: crate::raster::quadratic::Fill = crate::raster::quadratic::Fill::Rows;
}

/// Phong shading: normals and eye positions interpolated, every pixel lit.
#[derive(Copy, Clone, Debug, Default)]
pub struct Phong;

/// Phong shading with the even/odd fill of seed 003 (same pixels as [`Phong`]).
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
/// reach inside it; those triangles are Phong-shaded, the rest Gouraud-shaded.
/// [`crate::render::Stats::per_pixel`] counts the triangles that paid.
#[derive(Copy, Clone, Debug, Default)]
pub struct Adaptive;

impl Shading for Adaptive {
    const NAME: &'static str = "adaptive";
    const INTERPOLATE: bool = true;
    const ADAPTIVE: bool = true;
}
