//! The public surface in one `use`: `use fixshade::prelude::*;` brings the types a
//! program needs to set up a scene and render it.
//!
//! Everything else public (the stage modules' building blocks: setup, edge walker,
//! span internals, lighting setup, matrices) is reachable through its module and is
//! meant for benchmarks, tests and new span methods.
//!
//! ```
//! use fixshade::prelude::*;
//! let cam = Camera::perspective([Q16_16::from_int(4); 3], [Q16_16::ZERO; 3], Angle::from_degrees(45));
//! let scene = Scene::new(cam).with_shading(ShadingMode::Gouraud);
//! assert_eq!(scene.vertex_count(), 0);
//! ```

pub use crate::fixed::{Angle, Q16_16, Q2_14};
pub use crate::geometry::{Mesh, MeshError};
pub use crate::light::{Color, Light, LightKind, Material};

pub use crate::light::rgb;
pub use crate::present::linebuf::{render_lines, LineBufferProvider};
pub use crate::present::{DrawError, Renderer};
pub use crate::raster::parallel::{Counter, EvenOdd, KWay, Segment};
pub use crate::raster::sierpinski::{Sierpinski, SierpinskiExact};
pub use crate::raster::span::{Classic, DepthTest, Gradient, NoDepth, SpanMethod};
pub use crate::render::{Frame, RenderError, Stats, XfVertex};
pub use crate::scene::{Camera, CapacityError, Object, Placement, Projection, Scene, ShadingMode};
pub use crate::shade::{Flat, Gouraud, Shading};
pub use crate::specular::{BlinnExact, Specular};
pub use crate::target::{
    Framebuffer, Gray8, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, Strip, Target, TargetError,
};

#[cfg(feature = "embedded-graphics")]
pub use crate::present::eg::{CoveredPixel, EgFormat, Model};
