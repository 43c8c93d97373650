//! fixshade host simulator: the `fixshade` command line, scene files and meshes, the
//! fixed-point core run on the host, the f64 reference renderer, the accuracy and
//! timing tables, and charts.
//!
//! The modules are layers; each imports only the layers below it (a test keeps the
//! module graph acyclic: `cargo xtask cycles crates/sim-host/src`):
//!
//! ```text
//! cli        the only module that parses arguments (clap)
//! commands   what each command does
//! tables     measurements written as documents: report, specular, effects, raycast
//! render     one dispatch point, the core's frame loop, ray casting, reference, baking
//! image      images with coverage, PNG in and out, comparison (NMSE)
//! chart      the one PNG writer, a pixel font, a chart canvas
//! scene      descriptions (plain data), names, scene files, built-ins, meshes,
//!            conversion to the core, effect rules
//! ```
//!
//! and below them all the core, `fixshade`.

pub mod chart;
pub mod cli;
pub mod commands;
pub mod image;
pub mod render;
pub mod scene;
pub mod tables;

/// `$body` with the type `$S` bound to the span method named by `$name` (a
/// [`scene::desc::SpanName`]), from the core's registry
/// ([`fixshade::select_span_method!`]).
///
/// ```
/// use fixshade::raster::span::SpanMethod;
/// use fixshade_sim::scene::desc::SpanName;
/// let span = SpanName::named("kway3");
/// assert_eq!(fixshade_sim::with_span_method!(span, S => S::NAME), "kway3");
/// ```
#[macro_export]
macro_rules! with_span_method {
    ($name:expr, $S:ident => $body:expr) => {
        $crate::__core::select_span_method!(
            $crate::scene::desc::Named::name($name),
            $S => $body
        )
        .expect("every span method name is in the core's registry")
    };
}

#[doc(hidden)]
pub use fixshade as __core;
