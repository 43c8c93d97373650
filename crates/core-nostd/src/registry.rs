//! One list of every variant a program can select by name: span methods, specular
//! models, dividers, shading modes and pixel formats.
//!
//! The simulator's command line and scene files, the firmware images, the benchmarks
//! and the tests all take their variants from here, so a new span method (or specular
//! model, divider, …) is one line in this file next to its own module: everything that
//! iterates over the variants picks it up. The names are the types' own `NAME`s
//! ([`SpanMethod::NAME`], [`Divide::NAME`], [`Shading::NAME`],
//! [`PixelFormat::NAME`]; for specular models [`crate::specular::NAMES`]).
//!
//! Each list is a `macro_rules!` that calls a macro of yours with the list, so the
//! variants stay types (chosen at compile time, monomorphised where you use them):
//!
//! | list | your macro receives |
//! | --- | --- |
//! | [`for_each_span_method!`](crate::for_each_span_method) | `[args] Type, Type, …` |
//! | [`for_each_divider!`](crate::for_each_divider) | `[args] Type, Type, …` |
//! | [`for_each_specular!`](crate::for_each_specular) | `[args] (name, Type), (name, Type), …` |
//! | [`for_each_shading!`](crate::for_each_shading) | `[args] (name, ShadingMode, Type), …` |
//! | [`for_each_pixel_format!`](crate::for_each_pixel_format) | `[args] Type, Type, …` |
//!
//! `args` is whatever you write in brackets after your macro's name (nothing if you
//! write no brackets), handed through unchanged. A `; D` after it (a [`Divide`] type)
//! asks for the span methods or specular models that divide with `D`: `classic` with
//! `D` in its per-span division, every method with `D` in the triangle setup's
//! reciprocal ([`WithDivide`]), and Schlick's denominators with `D`.
//!
//! ```
//! use fixshade::raster::span::SpanMethod;
//!
//! // A table of (name, function) for a generic function, built from the list.
//! fn edge_values<S: SpanMethod>() -> bool {
//!     S::EDGE_VALUES
//! }
//! macro_rules! table {
//!     ([] $($S:ty),* $(,)?) => {
//!         [$((<$S as SpanMethod>::NAME, edge_values::<$S> as fn() -> bool)),*]
//!     };
//! }
//! let methods = fixshade::for_each_span_method!(table);
//! assert_eq!(methods.len(), fixshade::registry::SPAN_METHODS.len());
//! assert_eq!(methods[1].0, "gradient");
//!
//! // Pick a type by its run-time name.
//! let segment = fixshade::select_span_method!("segment8", S => S::NAME.len());
//! assert_eq!(segment, Some(8));
//! assert_eq!(fixshade::select_span_method!("bresenham", S => S::NAME.len()), None);
//! ```
//!
//! Adding a variant: write its type (with its `NAME`) in its module and add one
//! line to the list here; the simulator's `fixshade list`, the scene files, the
//! firmware tables, the benchmark table and the tests that run every variant take it
//! from the list.

#[cfg(doc)]
use crate::{
    divide::Divide, raster::span::SpanMethod, raster::span::WithDivide, shade::Shading,
    target::PixelFormat,
};

/// Calls `$cb!` with every span method, in the order `fixshade list` prints them.
///
/// `for_each_span_method!(cb)` calls `cb! { [] Classic, Gradient, … }`;
/// `for_each_span_method!(cb[a b])` calls `cb! { [a b] Classic, … }`;
/// `for_each_span_method!(cb; D)` lists the methods dividing with the divider `D`:
/// `WithDivide<Classic<D>, D>`, `WithDivide<Gradient, D>`, … (see the module docs).
///
/// ```
/// use fixshade::raster::span::SpanMethod;
/// macro_rules! names {
///     ([] $($S:ty),* $(,)?) => { [$(<$S as SpanMethod>::NAME),*] };
/// }
/// let names = fixshade::for_each_span_method!(names);
/// assert_eq!(names[..2], ["classic", "gradient"]);
/// ```
#[macro_export]
macro_rules! for_each_span_method {
    ($($cb:ident)::+ $([$($a:tt)*])?) => {
        $crate::__span_method_list! {
            $crate::__span_methods_plain [$($cb)::+ [$($($a)*)?]] $crate::divide::Exact
        }
    };
    ($($cb:ident)::+ $([$($a:tt)*])? ; $D:ty) => {
        $crate::__span_method_list! {
            $crate::__span_methods_with_divide [$($cb)::+ [$($($a)*)?] $D] $D
        }
    };
}

/// The span methods with a line on each, `classic` dividing per span with `$D`. The
/// one place that names them.
#[doc(hidden)]
#[macro_export]
macro_rules! __span_method_list {
    ($($cb:ident)::+ [$($a:tt)*] $D:ty) => {
        $($cb)::+! { [$($a)*]
            ($crate::raster::span::Classic<$D>,
             "per-span division of the end values (baseline)"),
            ($crate::raster::span::Gradient,
             "constant per-triangle increment (seed 000 §2.1)"),
            ($crate::raster::parallel::EvenOdd,
             "two accumulators over even and odd pixels; same pixels as gradient"),
            ($crate::raster::parallel::KWay<2>,
             "K accumulators stepping K·ΔI; same pixels as gradient"),
            ($crate::raster::parallel::KWay<3>,
             "K accumulators stepping K·ΔI; same pixels as gradient"),
            ($crate::raster::parallel::KWay<4>,
             "K accumulators stepping K·ΔI; same pixels as gradient"),
            ($crate::raster::parallel::Counter,
             "two interpolators from both span ends; same pixels as gradient"),
            ($crate::raster::parallel::Segment<2>,
             "P units filling segments of w pixels; same pixels as gradient"),
            ($crate::raster::parallel::Segment<4>,
             "P units filling segments of w pixels; same pixels as gradient"),
            ($crate::raster::parallel::Segment<8>,
             "P units filling segments of w pixels; same pixels as gradient"),
            ($crate::raster::parallel::Segment<16>,
             "P units filling segments of w pixels; same pixels as gradient"),
            ($crate::raster::parallel::Segment<32>,
             "P units filling segments of w pixels; same pixels as gradient"),
            ($crate::raster::parallel::Segment<64>,
             "P units filling segments of w pixels; same pixels as gradient"),
            ($crate::raster::sierpinski::Sierpinski,
             "midpoint subdivision with vertices snapped to even pixels (approximate)"),
            ($crate::raster::sierpinski::SierpinskiExact,
             "midpoint subdivision only where exact; same pixels as gradient"),
        }
    };
}

/// Hands the types of the list (without their lines) to the callback.
#[doc(hidden)]
#[macro_export]
macro_rules! __span_methods_plain {
    ([$($cb:ident)::+ [$($a:tt)*]] $(($S:ty, $line:expr)),* $(,)?) => {
        $($cb)::+! { [$($a)*] $($S),* }
    };
}

/// Wraps every method of the list in [`WithDivide`] with the divider `$D`.
#[doc(hidden)]
#[macro_export]
macro_rules! __span_methods_with_divide {
    ([$($cb:ident)::+ [$($a:tt)*] $D:ty] $(($S:ty, $line:expr)),* $(,)?) => {
        $($cb)::+! { [$($a)*] $($crate::raster::span::WithDivide<$S, $D>),* }
    };
}

/// The lines of the list, in order.
#[doc(hidden)]
#[macro_export]
macro_rules! __fixshade_lines {
    ([] $(($T:ty, $line:expr)),* $(,)?) => {
        &[$($line),*]
    };
}

/// Calls `$cb!` with every divider, in the order `fixshade list` prints them:
/// `cb! { [args] Exact, Table, ShiftAdd<4>, …, ShiftAddRounded<16> }`.
///
/// ```
/// use fixshade::divide::Divide;
/// macro_rules! names {
///     ([] $($D:ty),* $(,)?) => { [$(<$D as Divide>::NAME),*] };
/// }
/// let names = fixshade::for_each_divider!(names);
/// assert_eq!(names[..3], ["exact", "table", "shift-add-4"]);
/// assert_eq!(names.len(), 28);
/// ```
#[macro_export]
macro_rules! for_each_divider {
    ($($cb:ident)::+ $([$($a:tt)*])?) => {
        $($cb)::+! { [$($($a)*)?]
            $crate::divide::Exact,
            $crate::divide::Table,
            $crate::divide::ShiftAdd<4>,
            $crate::divide::ShiftAdd<5>,
            $crate::divide::ShiftAdd<6>,
            $crate::divide::ShiftAdd<7>,
            $crate::divide::ShiftAdd<8>,
            $crate::divide::ShiftAdd<9>,
            $crate::divide::ShiftAdd<10>,
            $crate::divide::ShiftAdd<11>,
            $crate::divide::ShiftAdd<12>,
            $crate::divide::ShiftAdd<13>,
            $crate::divide::ShiftAdd<14>,
            $crate::divide::ShiftAdd<15>,
            $crate::divide::ShiftAdd<16>,
            $crate::divide::ShiftAddRounded<4>,
            $crate::divide::ShiftAddRounded<5>,
            $crate::divide::ShiftAddRounded<6>,
            $crate::divide::ShiftAddRounded<7>,
            $crate::divide::ShiftAddRounded<8>,
            $crate::divide::ShiftAddRounded<9>,
            $crate::divide::ShiftAddRounded<10>,
            $crate::divide::ShiftAddRounded<11>,
            $crate::divide::ShiftAddRounded<12>,
            $crate::divide::ShiftAddRounded<13>,
            $crate::divide::ShiftAddRounded<14>,
            $crate::divide::ShiftAddRounded<15>,
            $crate::divide::ShiftAddRounded<16>,
        }
    };
}

/// Calls `$cb!` with every specular model and its name, in the order of
/// [`crate::specular::NAMES`]: `cb! { [args] ("exact", BlinnExact), ("schlick",
/// Schlick), … }`. With `; D`, the models that divide (Schlick's two) take `D`.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::Specular;
/// // Every model's cⁿ at c = ½, n = 8, in Q2.30 (exactly 2⁻⁸ = 2²² for `exact`).
/// macro_rules! at_half {
///     ([] $(($name:expr, $Sp:ty)),* $(,)?) => {
///         [$(($name, <$Sp>::eval(&<$Sp>::prepare(Q16_16::from_int(8)), 1 << 29))),*]
///     };
/// }
/// let values = fixshade::for_each_specular!(at_half);
/// assert_eq!(values[0], ("exact", 1 << 22));
/// assert!(values.iter().all(|(_, v)| (0..=1 << 30).contains(v)));
/// ```
#[macro_export]
macro_rules! for_each_specular {
    ($($cb:ident)::+ $([$($a:tt)*])?) => {
        $crate::for_each_specular! { $($cb)::+ $([$($a)*])? ; $crate::divide::Exact }
    };
    ($($cb:ident)::+ $([$($a:tt)*])? ; $D:ty) => {
        $crate::__specular_list! { $crate::__specular_plain [$($cb)::+ [$($($a)*)?]] $D }
    };
}

/// The specular models with their names and a line on each, Schlick's two dividing
/// with `$D`. The one place that names them.
#[doc(hidden)]
#[macro_export]
macro_rules! __specular_list {
    ($($cb:ident)::+ [$($a:tt)*] $D:ty) => {
        $($cb)::+! { [$($a)*]
            ($crate::specular::NAMES[0], $crate::specular::BlinnExact, "c^n"),
            (<$crate::specular::Schlick>::NAME, $crate::specular::Schlick<$D>,
             "c / (n - n·c + c)"),
            (<$crate::specular::SchlickModified>::NAME, $crate::specular::SchlickModified<$D>,
             "the seed's modified Schlick"),
            ($crate::specular::Quadratic::NAME, $crate::specular::Quadratic,
             "a·c² + (1 - a)·c, a(n) from a table"),
            ($crate::specular::CosQuadratic::NAME, $crate::specular::CosQuadratic,
             "(σ(c - 1) + 1)², σ = (n + 1)/3"),
            ($crate::specular::CosQuadraticEnergy::NAME, $crate::specular::CosQuadraticEnergy,
             "energy-conserving cosine-quadratic, (n + 6)/24.55 factor"),
        }
    };
}

/// Hands `(name, type)` of each model to the callback.
#[doc(hidden)]
#[macro_export]
macro_rules! __specular_plain {
    ([$($cb:ident)::+ [$($a:tt)*]] $(($name:expr, $Sp:ty, $line:expr)),* $(,)?) => {
        $($cb)::+! { [$($a)*] $(($name, $Sp)),* }
    };
}

/// The lines of the specular list, in order.
#[doc(hidden)]
#[macro_export]
macro_rules! __fixshade_specular_lines {
    ([] $(($name:expr, $Sp:ty, $line:expr)),* $(,)?) => {
        &[$($line),*]
    };
}

/// Calls `$cb!` with every shading mode of the core: its name, its
/// [`crate::scene::ShadingMode`] and its [`crate::shade`] type, `cb! { [args]
/// ("flat", ShadingMode::Flat, Flat), … }`.
///
/// ```
/// use fixshade::shade::Shading;
/// macro_rules! per_pixel {
///     ([] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => {
///         [$(($name, <$Sh as Shading>::PER_PIXEL)),*]
///     };
/// }
/// let modes = fixshade::for_each_shading!(per_pixel);
/// assert_eq!(modes[1], ("gouraud", false));
/// assert_eq!(modes[3], ("phong", true));
/// ```
#[macro_export]
macro_rules! for_each_shading {
    ($($cb:ident)::+ $([$($a:tt)*])?) => {
        $($cb)::+! { [$($($a)*)?]
            (<$crate::shade::Flat as $crate::shade::Shading>::NAME,
             $crate::scene::ShadingMode::Flat, $crate::shade::Flat),
            (<$crate::shade::Gouraud as $crate::shade::Shading>::NAME,
             $crate::scene::ShadingMode::Gouraud, $crate::shade::Gouraud),
            (<$crate::shade::QuadraticSurface as $crate::shade::Shading>::NAME,
             $crate::scene::ShadingMode::QuadraticSurface, $crate::shade::QuadraticSurface),
            (<$crate::shade::Phong as $crate::shade::Shading>::NAME,
             $crate::scene::ShadingMode::Phong, $crate::shade::Phong),
            (<$crate::shade::PhongEvenOdd as $crate::shade::Shading>::NAME,
             $crate::scene::ShadingMode::PhongEvenOdd, $crate::shade::PhongEvenOdd),
            (<$crate::shade::Adaptive as $crate::shade::Shading>::NAME,
             $crate::scene::ShadingMode::Adaptive, $crate::shade::Adaptive),
        }
    };
}

/// Calls `$cb!` with every pixel format: `cb! { [args] Rgb565Le, Rgb565Be, Rgb888,
/// Gray8 }`.
///
/// ```
/// use fixshade::target::PixelFormat;
/// macro_rules! bytes {
///     ([] $($P:ty),* $(,)?) => { [$((<$P as PixelFormat>::NAME, <$P as PixelFormat>::BYTES)),*] };
/// }
/// assert_eq!(fixshade::for_each_pixel_format!(bytes)[2], ("rgb888", 3));
/// ```
#[macro_export]
macro_rules! for_each_pixel_format {
    ($($cb:ident)::+ $([$($a:tt)*])?) => {
        $($cb)::+! { [$($($a)*)?]
            $crate::target::Rgb565Le,
            $crate::target::Rgb565Be,
            $crate::target::Rgb888,
            $crate::target::Gray8,
        }
    };
}

/// `Some($body)` with the type `$S` bound to the span method named `$name` (a
/// `&str`), `None` for a name that is not in the list. With `; D`, the methods divide
/// with `D` (as [`for_each_span_method!`](crate::for_each_span_method) with `; D`).
///
/// ```
/// use fixshade::raster::span::SpanMethod;
/// assert_eq!(fixshade::select_span_method!("kway3", S => S::EDGE_VALUES), Some(false));
/// ```
#[macro_export]
macro_rules! select_span_method {
    ($name:expr, $S:ident => $body:expr) => {
        $crate::for_each_span_method! { $crate::__fixshade_select_by_trait_name[
            $crate::raster::span::SpanMethod, $name, $S, $body
        ] }
    };
    ($name:expr, $S:ident => $body:expr ; $D:ty) => {
        $crate::for_each_span_method!($crate::__fixshade_select_by_trait_name[
            $crate::raster::span::SpanMethod, $name, $S, $body
        ]; $D)
    };
}

/// `Some($body)` with the type `$D` bound to the divider named `$name`, `None` for
/// an unknown name.
///
/// ```
/// use fixshade::divide::Divide;
/// assert_eq!(fixshade::select_divider!("shift-add-8", D => D::div(100, &D::recip(7))), Some(14));
/// ```
#[macro_export]
macro_rules! select_divider {
    ($name:expr, $D:ident => $body:expr) => {
        $crate::for_each_divider!($crate::__fixshade_select_by_trait_name[
            $crate::divide::Divide, $name, $D, $body
        ])
    };
}

/// `Some($body)` with the type `$Sp` bound to the specular model named `$name`,
/// `None` for an unknown name. With `; D`, Schlick's two divide with `D`.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::Specular;
/// let v = fixshade::select_specular!("exact", Sp => Sp::eval(&Sp::prepare(Q16_16::from_int(2)), 1 << 29));
/// assert_eq!(v, Some(1 << 28)); // 0.5² = 0.25 in Q2.30
/// ```
#[macro_export]
macro_rules! select_specular {
    ($name:expr, $Sp:ident => $body:expr) => {
        $crate::for_each_specular!($crate::__fixshade_select_by_listed_name[$name, $Sp, $body])
    };
    ($name:expr, $Sp:ident => $body:expr ; $D:ty) => {
        $crate::for_each_specular!($crate::__fixshade_select_by_listed_name[$name, $Sp, $body]; $D)
    };
}

/// Picks the type listed with the name `$name`.
#[doc(hidden)]
#[macro_export]
macro_rules! __fixshade_select_by_listed_name {
    ([$name:expr, $X:ident, $body:expr] $(($listed:expr, $T:ty)),* $(,)?) => {{
        let name: &str = $name;
        $(
            if name == $listed {
                #[allow(dead_code)]
                type $X = $T;
                Some($body)
            } else
        )* {
            None
        }
    }};
}

/// Picks the type whose `<T as $Trait>::NAME` equals `$name`.
#[doc(hidden)]
#[macro_export]
macro_rules! __fixshade_select_by_trait_name {
    ([$Trait:path, $name:expr, $X:ident, $body:expr] $($T:ty),* $(,)?) => {{
        let name: &str = $name;
        $(
            if name == <$T as $Trait>::NAME {
                #[allow(dead_code)]
                type $X = $T;
                Some($body)
            } else
        )* {
            None
        }
    }};
}

/// Lists names of types implementing a trait with `NAME`.
#[doc(hidden)]
#[macro_export]
macro_rules! __fixshade_names_by_trait {
    ([$Trait:path] $($T:ty),* $(,)?) => {
        &[$(<$T as $Trait>::NAME),*]
    };
}

/// Lists the first field of each entry.
#[doc(hidden)]
#[macro_export]
macro_rules! __fixshade_first_names {
    ([] $(($name:expr, $($rest:tt)*)),* $(,)?) => {
        &[$($name),*]
    };
}

/// Every span method's name, in [`for_each_span_method!`](crate::for_each_span_method) order.
///
/// ```
/// assert_eq!(fixshade::registry::SPAN_METHODS.len(), 15);
/// ```
pub const SPAN_METHODS: &[&str] =
    for_each_span_method!(__fixshade_names_by_trait[crate::raster::span::SpanMethod]);

/// A line on what each span method does, in [`for_each_span_method!`](crate::for_each_span_method) order (for
/// `fixshade list`).
pub const SPAN_METHOD_LINES: &[&str] = __span_method_list!(__fixshade_lines[] crate::divide::Exact);

/// A line on each specular model, in [`for_each_specular!`](crate::for_each_specular) order.
pub const SPECULAR_LINES: &[&str] =
    __specular_list!(__fixshade_specular_lines[] crate::divide::Exact);

/// Every divider's name, in [`for_each_divider!`](crate::for_each_divider) order.
pub const DIVIDERS: &[&str] = for_each_divider!(__fixshade_names_by_trait[crate::divide::Divide]);

/// Every specular model's name, in [`for_each_specular!`](crate::for_each_specular) order (the same as
/// [`crate::specular::NAMES`]).
///
/// ```
/// assert_eq!(fixshade::registry::SPECULAR_MODELS, fixshade::specular::NAMES);
/// ```
pub const SPECULAR_MODELS: &[&str] = for_each_specular!(__fixshade_first_names);

/// Every shading mode's name, in [`for_each_shading!`](crate::for_each_shading) order.
pub const SHADINGS: &[&str] = for_each_shading!(__fixshade_first_names);

/// Every pixel format's name, in [`for_each_pixel_format!`](crate::for_each_pixel_format) order.
pub const PIXEL_FORMATS: &[&str] =
    for_each_pixel_format!(__fixshade_names_by_trait[crate::target::PixelFormat]);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::divide::Divide;
    use crate::raster::span::SpanMethod;

    fn distinct(names: &[&str]) {
        for (i, a) in names.iter().enumerate() {
            assert!(!names[..i].contains(a), "{a} listed twice");
        }
    }

    #[test]
    fn names_are_distinct_and_selectable() {
        assert_eq!(SPAN_METHOD_LINES.len(), SPAN_METHODS.len());
        assert_eq!(SPECULAR_LINES.len(), SPECULAR_MODELS.len());
        for list in [
            SPAN_METHODS,
            DIVIDERS,
            SPECULAR_MODELS,
            SHADINGS,
            PIXEL_FORMATS,
        ] {
            distinct(list);
        }
        for name in SPAN_METHODS {
            assert_eq!(select_span_method!(name, S => S::NAME), Some(*name));
            assert_eq!(
                select_span_method!(name, S => S::NAME; crate::divide::Table),
                Some(*name)
            );
        }
        for name in DIVIDERS {
            assert_eq!(select_divider!(name, D => D::NAME), Some(*name));
        }
        assert_eq!(select_divider!("shift-add-17", D => D::NAME), None);
        for name in SPECULAR_MODELS {
            assert!(select_specular!(name, Sp => core::mem::size_of::<Sp>()).is_some());
        }
        assert!(select_specular!("phong", Sp => ()).is_none());
    }

    #[test]
    fn shading_modes_match_their_types() {
        use crate::scene::ShadingMode;
        use crate::shade::Shading;
        macro_rules! check {
            ([] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => {
                [$(($name, $mode, <$Sh as Shading>::NAME)),*]
            };
        }
        let all: [(&str, ShadingMode, &str); 6] = for_each_shading!(check);
        for (name, _, type_name) in all {
            assert_eq!(name, type_name);
        }
        assert_eq!(all[5].1, ShadingMode::Adaptive);
    }
}
