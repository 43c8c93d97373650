//! Names selectable in scene files and on the command line: span methods, specular
//! models, dividers, shading modes and pixel formats, each a position in the core's
//! registry ([`fixshade::registry`]), so a variant added there is selectable here
//! without a change to the simulator.

use std::fmt;

/// Names of the values of a type selectable by name in scene files and on the
/// command line.
pub trait Named: Sized + Copy + 'static {
    /// What the names denote, for error messages ("span method").
    const WHAT: &'static str;
    /// Every value with its name.
    const ALL: &'static [(Self, &'static str)];

    /// The value's name.
    fn name(self) -> &'static str
    where
        Self: PartialEq,
    {
        Self::ALL
            .iter()
            .find(|(v, _)| *v == self)
            .map(|(_, n)| *n)
            .unwrap_or("?")
    }

    /// Parses a name; the error lists the valid names.
    fn parse(name: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name))
            .map(|(v, _)| *v)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(_, n)| *n).collect();
                format!(
                    "unknown {} `{}`; expected one of: {}",
                    Self::WHAT,
                    name,
                    names.join(", ")
                )
            })
    }
}

/// Position of `name` in `list`, at compile time.
const fn position(list: &[&str], name: &str) -> Option<usize> {
    let mut i = 0;
    while i < list.len() {
        let (a, b) = (list[i].as_bytes(), name.as_bytes());
        if a.len() == b.len() {
            let mut k = 0;
            while k < a.len() && a[k] == b[k] {
                k += 1;
            }
            if k == a.len() {
                return Some(i);
            }
        }
        i += 1;
    }
    None
}

/// A name type over a list of names: the value is the position in the list.
macro_rules! name_type {
    ($(#[$meta:meta])* $T:ident, $what:literal, $list:expr) => {
        $(#[$meta])*
        #[derive(Clone, Copy, PartialEq, Eq, Hash)]
        pub struct $T(u8);

        impl $T {
            /// Every name, in the registry's order.
            pub const NAMES: &'static [&'static str] = $list;

            /// The value named `name`; a name not in the list does not compile in a
            /// `const` (and panics elsewhere: use [`Named::parse`] for input).
            pub const fn named(name: &str) -> $T {
                match position(Self::NAMES, name) {
                    Some(i) => $T(i as u8),
                    None => panic!(concat!("not a ", $what)),
                }
            }

            /// Position in [`Self::NAMES`] (and in the registry's list).
            pub const fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl Named for $T {
            const WHAT: &'static str = $what;
            const ALL: &'static [(Self, &'static str)] = &{
                let mut all = [($T(0), ""); $list.len()];
                let mut i = 0;
                while i < all.len() {
                    all[i] = ($T(i as u8), $list[i]);
                    i += 1;
                }
                all
            };
            fn name(self) -> &'static str {
                Self::NAMES[self.index()]
            }
        }

        impl fmt::Debug for $T {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }

        impl fmt::Display for $T {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

name_type!(
    /// A span method ([`fixshade::for_each_span_method!`]).
    SpanName,
    "span method",
    fixshade::registry::SPAN_METHODS
);

name_type!(
    /// A specular model ([`fixshade::for_each_specular!`]).
    SpecularName,
    "specular model",
    fixshade::registry::SPECULAR_MODELS
);

name_type!(
    /// A divider ([`fixshade::for_each_divider!`]): used by the classic span
    /// division, the triangle setup's reciprocal and Schlick's denominator.
    DivideName,
    "divider",
    fixshade::registry::DIVIDERS
);

name_type!(
    /// An output pixel format ([`fixshade::for_each_pixel_format!`]).
    FormatName,
    "pixel format",
    fixshade::registry::PIXEL_FORMATS
);

/// The shading modes: the core's ([`fixshade::for_each_shading!`]) and the
/// simulator's ray caster.
const SHADINGS: [&str; fixshade::registry::SHADINGS.len() + 1] = {
    let core = fixshade::registry::SHADINGS;
    let mut all = [RAYCAST; fixshade::registry::SHADINGS.len() + 1];
    let mut i = 0;
    while i < core.len() {
        all[i] = core[i];
        i += 1;
    }
    all
};

/// Name of the ray-casting shading mode ([`crate::render::raycast`]), the one the
/// core's rasterizer does not have.
const RAYCAST: &str = "raycast";

name_type!(
    /// A shading mode: one of the core's ([`fixshade::for_each_shading!`]) or
    /// `raycast`, per-pixel ray casting sampled by pixel segments.
    ShadingName,
    "shading mode",
    &SHADINGS
);

impl SpanName {
    /// Per-span division of the end values (the idx3d baseline).
    pub const CLASSIC: SpanName = SpanName::named("classic");
    /// The constant per-triangle increment (seed 000 §2.1), the default.
    pub const GRADIENT: SpanName = SpanName::named("gradient");
}

impl SpecularName {
    /// Exact `cⁿ`, the default.
    pub const EXACT: SpecularName = SpecularName::named("exact");
}

impl DivideName {
    /// Full-precision integer division, the default: the pipeline draws the plain
    /// span types, bit-identical to the pipeline before the divider seam.
    pub const EXACT: DivideName = DivideName::named("exact");
}

impl Default for DivideName {
    fn default() -> Self {
        DivideName::EXACT
    }
}

impl FormatName {
    /// RGB 5-6-5, little-endian bytes.
    pub const RGB565LE: FormatName = FormatName::named("rgb565le");
    /// RGB 5-6-5, big-endian bytes (what ST7789/ILI9341 take over SPI).
    pub const RGB565BE: FormatName = FormatName::named("rgb565be");
    /// RGB 8-8-8.
    pub const RGB888: FormatName = FormatName::named("rgb888");
    /// 8-bit grey, `(77 R + 150 G + 29 B) / 256`.
    pub const GRAY8: FormatName = FormatName::named("gray8");

    /// The largest integer each output channel holds (the core's `PixelFormat::MAX`).
    pub fn channel_max(self) -> [u32; 3] {
        macro_rules! maxima {
            ([] $($P:ty),* $(,)?) => { [$(<$P as fixshade::target::PixelFormat>::MAX),*] };
        }
        fixshade::for_each_pixel_format!(maxima)[self.index()]
    }

    /// True for a grey format (one channel, `PixelFormat::GRAY`).
    pub fn is_gray(self) -> bool {
        macro_rules! grey {
            ([] $($P:ty),* $(,)?) => { [$(<$P as fixshade::target::PixelFormat>::GRAY),*] };
        }
        fixshade::for_each_pixel_format!(grey)[self.index()]
    }

    /// Expands channel integers of the format (each `0..=channel_max`) to 8 bits,
    /// rounding to nearest: `v8 = (v * 255 + max / 2) / max`. Grey formats repeat
    /// their one channel.
    pub fn expand(self, c: [u32; 3]) -> [u8; 3] {
        let m = self.channel_max();
        let e = |v: u32, max: u32| ((v.min(max) * 255 + max / 2) / max) as u8;
        [e(c[0], m[0]), e(c[1], m[1]), e(c[2], m[2])]
    }
}

impl ShadingName {
    /// One colour per triangle: its last (provoking) vertex's, as OpenGL does.
    pub const FLAT: ShadingName = ShadingName::named("flat");
    /// Vertex colours interpolated linearly in screen space.
    pub const GOURAUD: ShadingName = ShadingName::named("gouraud");
    /// Quadratic intensity surface through the vertex and edge-midpoint colours
    /// (seed 003); its reference is the exact Phong render.
    pub const QUADRATIC: ShadingName = ShadingName::named("quadratic");
    /// Per-pixel lighting from interpolated normals.
    pub const PHONG: ShadingName = ShadingName::named("phong");
    /// Phong with the even/odd fill of seed 003 (the same pixels).
    pub const PHONG_EVEN_ODD: ShadingName = ShadingName::named("phong-even-odd");
    /// Phong where a highlight can reach inside a triangle, Gouraud elsewhere;
    /// its reference is the exact Phong render.
    pub const ADAPTIVE: ShadingName = ShadingName::named("adaptive");
    /// Per-pixel ray casting sampled by pixel segments (seed 002 §2.6); its
    /// reference is the exact Phong render.
    pub const RAYCAST: ShadingName = ShadingName::named(RAYCAST);

    /// The core's shading mode, `None` for the ray caster.
    pub fn core(self) -> Option<fixshade::scene::ShadingMode> {
        macro_rules! modes {
            ([] $(($name:expr, $mode:expr, $Sh:ty)),* $(,)?) => { [$($mode),*] };
        }
        let modes: &[fixshade::scene::ShadingMode] = &fixshade::for_each_shading!(modes);
        modes.get(self.index()).copied()
    }

    /// True if the matching f64 reference is the per-pixel (Phong) render: every
    /// shading but flat and Gouraud.
    pub fn phong_reference(self) -> bool {
        !matches!(self, ShadingName::FLAT | ShadingName::GOURAUD)
    }

    /// True for the shadings with fills of their own, which ignore the span method
    /// and cover what `gradient` covers (quadratic, Phong, adaptive).
    pub fn own_fill(self) -> bool {
        self.core().is_some() && self.phong_reference()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trips<T: Named + PartialEq + std::fmt::Debug>() {
        for (v, n) in T::ALL {
            assert_eq!(T::parse(n), Ok(*v), "{n}");
            assert_eq!(v.name(), *n);
        }
    }

    #[test]
    fn every_name_round_trips() {
        round_trips::<SpanName>();
        round_trips::<SpecularName>();
        round_trips::<DivideName>();
        round_trips::<FormatName>();
        round_trips::<ShadingName>();
        assert_eq!(SpanName::ALL.len(), fixshade::registry::SPAN_METHODS.len());
        assert_eq!(ShadingName::ALL.len(), 7);
        assert_eq!(DivideName::ALL.len(), 28);
        assert_eq!(
            DivideName::parse("shift-add-8"),
            Ok(DivideName::named("shift-add-8"))
        );
        let e = DivideName::parse("shift-add-17").unwrap_err();
        assert!(e.contains("divider `shift-add-17`") && e.contains("shift-add-rounded-4"));
        assert_eq!(ShadingName::RAYCAST.core(), None);
        assert_eq!(
            ShadingName::ADAPTIVE.core(),
            Some(fixshade::scene::ShadingMode::Adaptive)
        );
        assert!(ShadingName::QUADRATIC.own_fill() && !ShadingName::RAYCAST.own_fill());
    }

    #[test]
    fn expand_rounds_to_nearest() {
        assert_eq!(FormatName::RGB565LE.expand([31, 63, 0]), [255, 255, 0]);
        assert_eq!(FormatName::RGB565LE.expand([16, 32, 1]), [132, 130, 8]);
        assert_eq!(FormatName::RGB888.expand([7, 8, 9]), [7, 8, 9]);
        assert!(FormatName::GRAY8.is_gray() && !FormatName::RGB888.is_gray());
    }
}
