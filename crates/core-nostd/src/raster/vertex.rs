//! The rasterizer's input: a vertex in screen space ([`ScreenVertex`], Q12.4
//! coordinates) and the guard band its coordinates must lie in.

/// Subpixel bits of screen coordinates (Q12.4).
pub const SUBPIXEL_BITS: u32 = 4;

/// Guard band: screen coordinates must satisfy |x|, |y| < `GUARD` (Q12.4), i.e. lie
/// within ±4096 pixels of the origin. Anything inside is rasterized without clipping.
pub const GUARD: i32 = 4096 << SUBPIXEL_BITS;

/// True if a vertex lies outside the guard band (such triangles are not drawn).
/// `unsigned_abs`: a coordinate at `i32::MIN` is outside too, without overflow.
#[inline]
pub(crate) fn outside_guard(p: [(i32, i32); 3]) -> bool {
    p.iter()
        .any(|(x, y)| x.unsigned_abs() >= GUARD as u32 || y.unsigned_abs() >= GUARD as u32)
}

/// A vertex in screen space.
///
/// ```
/// use fixshade::raster::ScreenVertex;
/// // Pixel (10.5, 3.25), depth 0.5, full red in RGB565 channel units (Q.16).
/// let v = ScreenVertex { x: 168, y: 52, z: 32767 << 16, c: [31 << 16, 0, 0] };
/// assert_eq!((v.x / 16, v.y / 16), (10, 3));
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct ScreenVertex {
    /// x in Q12.4 (1/16 pixel), the left edge of the frame at 0.
    pub x: i32,
    /// y in Q12.4, the top edge of the frame at 0, y down.
    pub y: i32,
    /// Depth in Q16.16: `floor(d · 65534 · 2¹⁶)` for d in [0, 1], near = 0.
    pub z: u32,
    /// Colour channels in the target format's channel units, Q.16 (R, G, B; grey
    /// formats use channel 0).
    pub c: [i32; 3],
}
