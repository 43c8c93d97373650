//! fixshade core.
#![no_std]
#![deny(missing_docs, unsafe_code, trivial_numeric_casts)]
#![deny(clippy::float_arithmetic)]

pub mod clip;
pub mod fixed;
pub mod geometry;
pub mod light;
pub mod math;
pub mod raster;
pub mod render;
pub mod scene;
pub mod shade;
pub mod target;
