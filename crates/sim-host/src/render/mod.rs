//! Rendering on the host: the one dispatch point from names to the core's types
//! ([`dispatch`]), the core's frame loop ([`frame`]), the run-time divider and
//! specular model ([`host`]), ray casting ([`raycast`]), the f64 reference renderer
//! ([`mod@reference`]) and baking for flash ([`bake`]).

/// `$body` with the type `$P` bound to the core's pixel format named by `$format` (a
/// [`crate::scene::desc::FormatName`]), from the registry.
macro_rules! with_format {
    ($format:expr, $P:ident => $body:expr) => {
        fixshade::for_each_pixel_format!(select_format[$format, $P, $body])
    };
}

/// The arm of [`with_format`] for each pixel format of the registry.
macro_rules! select_format {
    ([$format:expr, $P:ident, $body:expr] $($F:ty),* $(,)?) => {{
        let i = ($format).index();
        let mut at = 0;
        let mut out = None;
        $(
            if i == at {
                type $P = $F;
                out = Some($body);
            }
            #[allow(unused_assignments)]
            {
                at += 1;
            }
        )*
        out.expect("a pixel format of the registry")
    }};
}

pub mod bake;
pub mod dispatch;
pub mod frame;
pub mod host;
pub mod output;
pub mod raycast;
pub mod reference;

pub use frame::{render, render_chunked, specular_pipeline, time_frame, Drawn, Pipeline};
pub use output::Render;
pub use reference::{matching_reference, reference};
