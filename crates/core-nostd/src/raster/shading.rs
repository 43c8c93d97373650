//! The shading interface of the rasterizer: what a span loop needs to know of the
//! shading mode it draws with. The modes themselves ([`crate::shade::Flat`],
//! [`crate::shade::Gouraud`], …) live in [`crate::shade`].

/// A shading mode.
///
/// ```
/// use fixshade::shade::{Flat, Gouraud, Phong, QuadraticSurface, Shading};
/// assert!(!Flat::INTERPOLATE && Gouraud::INTERPOLATE);
/// assert!(QuadraticSurface::QUADRATIC && Phong::PER_PIXEL);
/// assert_eq!(Gouraud::NAME, "gouraud");
/// ```
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
    const FILL: Fill = Fill::Blocks;
    /// True for Phong shading: [`crate::render::Frame`] interpolates normals and
    /// eye positions and lights every pixel ([`crate::raster::phong`]).
    const PER_PIXEL: bool = false;
    /// With `PER_PIXEL`: the even/odd fill (two accumulators per attribute).
    const EVEN_ODD: bool = false;
    /// True for adaptive shading: [`crate::render::Frame`] decides per triangle
    /// between Phong and Gouraud ([`crate::shade::Adaptive`]).
    const ADAPTIVE: bool = false;
}

/// How the quadratic surface is filled ([`crate::raster::quadratic`]).
///
/// ```
/// use fixshade::raster::quadratic::{draw_quadratic, Fill};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::ScreenVertex;
/// use fixshade::target::{Framebuffer, Gray8};
/// let draw = |fill: Fill| {
///     let mut px = [0u8; 32 * 32];
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 32, 32).unwrap();
///     let v = |x: i32, y: i32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [g << 16; 3] };
///     let mid = [[200 << 16; 3], [120 << 16; 3], [60 << 16; 3]];
///     draw_quadratic::<Gray8, _, NoDepth>(&mut fb, [v(1, 1, 10), v(3, 31, 90), v(30, 4, 250)], mid, fill);
///     px
/// };
/// // The 2×2 block scheme of seed 003 and the row fill give the same pixels.
/// assert_eq!(draw(Fill::Blocks), draw(Fill::Rows));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Fill {
    /// Row by row, one forward-difference unit.
    Rows,
    /// Seed 003: 2×2 blocks over two scanlines, four units, stepping +2 rows.
    Blocks,
}
