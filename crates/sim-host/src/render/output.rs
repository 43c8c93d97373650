//! What a render of a scene gives: the image with its coverage, the frame's bytes
//! and the core's statistics.

use fixshade::render::Stats;

use crate::image::Image;

/// The result of a fixed-point render.
#[derive(Clone, Debug)]
pub struct Render {
    /// The image (with coverage).
    pub image: Image,
    /// The framebuffer bytes in memory order.
    pub bytes: Vec<u8>,
    /// Draw statistics.
    pub stats: Stats,
}
