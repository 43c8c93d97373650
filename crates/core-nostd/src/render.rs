//! The pipeline, end to end: vertex stage, clip & cull, rasterization.
//!
//! [`Frame::prepare`] runs the vertex stage once per frame: every vertex of every
//! object is transformed, projected and lit once (not once per triangle corner) into
//! a caller-owned cache of [`XfVertex`]. [`Frame::draw`] then rasterizes into any
//! [`Target`](crate::target::Target), as many times as needed: once for a framebuffer, or once per strip.
//!
//! ```
//! use fixshade::fixed::{Angle, Q16_16, Q2_14};
//! use fixshade::geometry::Mesh;
//! use fixshade::light::{Light, Material};
//! use fixshade::raster::span::Gradient;
//! use fixshade::render::{Frame, XfVertex};
//! use fixshade::scene::{Camera, Object, Placement, Projection, Scene};
//! use fixshade::target::{Framebuffer, Rgb565Le, Target};
//!
//! // One triangle facing the camera.
//! static POS: [[Q16_16; 3]; 3] = [
//!     [Q16_16::from_int(-1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::from_int(1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
//! ];
//! static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
//! static TRI: [[u16; 3]; 1] = [[0, 1, 2]];
//!
//! let camera = Camera {
//!     eye: [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)],
//!     target: [Q16_16::ZERO; 3],
//!     up: [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO],
//!     projection: Projection::Perspective {
//!         fovy: Angle::from_degrees(60),
//!         near: Q16_16::ONE,
//!         far: Q16_16::from_int(10),
//!     },
//! };
//! let mut scene = Scene::new(camera);
//! let white = [Q16_16::ONE; 3];
//! scene.add_light(Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white)).unwrap();
//! let mesh = Mesh::new(&POS, &NRM, &TRI).unwrap();
//! scene
//!     .add_object(Object { mesh, placement: Placement::default(), material: Material::default(), back_material: None })
//!     .unwrap();
//!
//! let (w, h) = (32, 24);
//! let mut color = [0u16; 32 * 24];
//! let mut depth = [0xFFFFu16; 32 * 24];
//! let mut cache = [XfVertex::default(); 3];
//! let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), w, h).unwrap();
//! let frame = Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache).unwrap();
//! let stats = frame.draw::<Gradient, _>(&mut fb).unwrap();
//! assert_eq!(stats.drawn, 1);
//! assert!(stats.pixels > 60, "{stats:?}");
//! ```

mod adaptive;
pub mod bands;
mod draw;
mod fills;
mod frame;
mod walk;

pub use bands::{BandMemory, Binned, Bins};
pub use frame::{Frame, FrameSetup, RenderError, Stats, XfVertex, NEEDED, OUTSIDE};
