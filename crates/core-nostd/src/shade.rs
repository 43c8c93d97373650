//! Shading modes: what a triangle's colour does across its pixels.
//!
//! [`Flat`] gives the whole triangle the colour of its last (provoking) vertex, as
//! OpenGL does; [`Gouraud`] interpolates the vertex colours linearly in screen space.
//! The choice is a type, so the span loop of a flat triangle carries no colour
//! interpolation at all.

/// A shading mode.
pub trait Shading {
    /// Name used by the CLI and scene files.
    const NAME: &'static str;
    /// True if colours are interpolated across the triangle.
    const INTERPOLATE: bool;
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
