//! `fixshade`: a `no_std`, integer-only triangle rasterizer for microcontroller LCD
//! framebuffers.
//!
//! The crate reads like its pipeline, one module per stage:
//!
//! ```text
//! Scene (meshes in flash, camera, lights, materials)            scene, geometry
//!   -> vertex stage   fixed-point transform, per-vertex lighting  math, light, render
//!   -> clip & cull    near/far planes, guard band, back faces     clip
//!   -> setup          Q12.4 screen coordinates, plane gradients   raster::setup
//!   -> edge walker    Obidnyk–Petukh stepper, top-left rule       raster::edge
//!   -> span filler    classic or constant-gradient spans          raster::span
//!   -> pixel ops      u16 depth test, pack, write                 raster::span, target
//!   -> target         framebuffer or strip of rows                target
//! ```
//!
//! There is no floating point anywhere (`clippy::float_arithmetic` is denied), no
//! allocation, and no `unsafe` but the `asm!` blocks of the Cortex-M span loops
//! ([`raster::dsp`] and Gradient's packed loop), each allowed on its own with a
//! SAFETY comment. All arithmetic is integer, so the same frame has the same bytes
//! on the host and on every MCU. Overflow bounds are written next to the arithmetic
//! that relies on them.
//!
//! Start with [`prelude`] and [`present::Renderer`] (the example below); the stage
//! modules hold the building blocks, each with its contract in its docs.
//!
//! Numeric conventions: screen coordinates Q12.4 (1/16 pixel) within a guard band of
//! ±4096 pixels; pixel (x, y) is sampled at its centre; colours interpolate in the
//! target format's channel units with 16 fraction bits; depth is u16 in the buffer and
//! Q16.16 while interpolated; normals are Q2.14; angles are binary fractions of a turn.
//!
//! # Using the library
//!
#![doc = include_str!("../docs/library.md")]
#![no_std]
#![deny(missing_docs, unsafe_code, trivial_numeric_casts)]
#![deny(clippy::float_arithmetic)]

mod arrays;
pub mod clip;
#[cfg(feature = "defmt")]
mod defmt_impls;
pub mod divide;
#[doc(hidden)]
pub mod doc_support;
pub mod effects;
pub mod fixed;
pub mod geometry;
pub mod light;
pub mod math;
pub mod prelude;
pub mod present;
pub mod raster;
pub mod raycast;
pub mod registry;
pub mod render;
pub mod sampler;
pub mod scene;
pub mod shade;
pub mod specular;
pub mod target;

/// The README's code blocks, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
