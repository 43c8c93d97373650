//! The divider, the specular model and two-sided lighting chosen on the command line
//! or in a scene file, as two types whose calls forward to the core's variant
//! selected at run time.
//!
//! The core takes both as types (`Classic<ShiftAdd<8>>`, `Schlick<Table>`), which a
//! firmware names once. The simulator offers every divider and specular model on top
//! of every span method, shading mode and pixel format; monomorphising the pipeline
//! for each would multiply its build time by their number. So the host draws the
//! approximate dividers through [`HostDivide`] and every specular model through
//! [`HostSpecular`]: `Divide::recip` and `Specular::prepare` (once per divisor, once
//! per material and frame) store the selected variant's own prepared value in an
//! enum with one variant per registry entry; `div` and `eval` branch once on it (one
//! `match`, a jump table) and run the variant's code. The results are exactly the
//! core variant's; only the host's timing includes the branch. With `exact`
//! selected, [`HostDivide`]'s `Divide::is_exact` is true, so every stage keeps its
//! own full-precision division, as with the core's `Exact`: every frame takes
//! `HostDivide` for every divider, `exact` included, and is bit-identical to the
//! plain types'. Likewise [`HostSpecular`]'s `Specular::enabled` and
//! `Specular::two_sided` are the selection's, where the core's `NoSpecular` and
//! `TwoSided` answer with a constant: frames with and without the specular term,
//! one-sided and two-sided, share one set of draws, which skips the same code
//! (the stages ask once per light, vertex, triangle or pixel).
//!
//! The selection is per thread and set only by [`with_selection`], which
//! [`crate::render::dispatch`] wraps around the vertex stage and the draw of a frame.
//!
//! Both types take their variants from the core's registry
//! ([`fixshade::for_each_divider!`], [`fixshade::for_each_specular!`]) in its
//! order, so the position of a [`DivideName`] or [`SpecularName`] is the position of
//! its variant here.

use std::cell::Cell;

use fixshade::divide::Divide;
use fixshade::fixed::Q16_16;
use fixshade::specular::Specular;

use crate::scene::desc::{DivideName, SpecularName};

/// What [`HostDivide`] and [`HostSpecular`] forward to.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    /// The divider.
    pub divide: DivideName,
    /// The specular model.
    pub specular: SpecularName,
    /// The specular term: off for frames that have none (no specular colour on
    /// their lights or materials, the exact divider, see
    /// [`crate::render::specular_pipeline`]), which then skip its code as
    /// [`fixshade::effects::NoSpecular`] does.
    pub specular_term: bool,
    /// Two-sided lighting.
    pub two_sided: bool,
}

impl Selection {
    /// The exact divider and model with the specular term, one-sided: the
    /// selection outside [`with_selection`].
    pub const EXACT: Selection = Selection {
        divide: DivideName::EXACT,
        specular: SpecularName::EXACT,
        specular_term: true,
        two_sided: false,
    };
}

thread_local! {
    static SELECTED: Cell<Selection> = const { Cell::new(Selection::EXACT) };
}

/// Runs `f` with `sel` selected for [`HostDivide`] and [`HostSpecular`] on this
/// thread, and restores the previous selection after.
pub fn with_selection<R>(sel: Selection, f: impl FnOnce() -> R) -> R {
    struct Restore(Selection);
    impl Drop for Restore {
        fn drop(&mut self) {
            SELECTED.with(|s| s.set(self.0));
        }
    }
    let _restore = Restore(SELECTED.with(|s| s.replace(sel)));
    f()
}

fn selected() -> Selection {
    SELECTED.with(Cell::get)
}

/// Pairs the entries of a registry list with variant names, then hands the pairs to
/// `$emit`. Forty names: a registry list longer than that fails to compile here.
macro_rules! with_slots {
    ($emit:ident [$($pre:tt)*] $($T:ty),* $(,)?) => {
        with_slots! { @zip $emit [$($pre)*] []
            [S0 S1 S2 S3 S4 S5 S6 S7 S8 S9 S10 S11 S12 S13 S14 S15 S16 S17 S18 S19
             S20 S21 S22 S23 S24 S25 S26 S27 S28 S29 S30 S31 S32 S33 S34 S35 S36 S37
             S38 S39]
            [$($T,)*] }
    };
    (@zip $emit:ident [$($pre:tt)*] [$($done:tt)*] [$S:ident $($Ss:ident)*] [$T:ty, $($Ts:ty,)*]) => {
        with_slots! { @zip $emit [$($pre)*] [$($done)* ($S, $T)] [$($Ss)*] [$($Ts,)*] }
    };
    (@zip $emit:ident [$($pre:tt)*] [$($done:tt)*] [$($Ss:ident)*] []) => {
        $emit! { $($pre)* $($done)* }
    };
}

/// Returns `$e` with the type `$X` bound to the entry of `$(($S, $T))*` at position
/// `$i`, wrapped in the variant `$S` of `$Enum` if given.
macro_rules! at_index {
    ($i:expr, [$(($S:ident, $T:ty))*], $X:ident => $e:expr, in $Enum:ident) => {
        at_index!($i, [$(($S, $T, $Enum::$S))*], $X => $e)
    };
    ($i:expr, [$(($S:ident, $T:ty))*], $X:ident => $e:expr) => {
        at_index!($i, [$(($S, $T, std::convert::identity))*], $X => $e)
    };
    ($i:expr, [$(($S:ident, $T:ty, $wrap:expr))*], $X:ident => $e:expr) => {{
        let i = $i;
        let mut at = 0;
        $(
            if i == at {
                type $X = $T;
                return $wrap($e);
            }
            at += 1;
        )*
        unreachable!("{i} of {at}")
    }};
}

// ---------------------------------------------------------------------------------
// Dividers.

/// The registry's dividers without their names (for [`with_slots`]).
macro_rules! dividers {
    ([] $($D:ty),* $(,)?) => {
        with_slots! { host_divide [] $($D),* }
    };
}

/// [`HostDivide`] and its [`HostRecip`] over `(slot, divider)` pairs.
macro_rules! host_divide {
    ($(($S:ident, $D:ty))*) => {
        /// Prepared divisor of [`HostDivide`]: the selected divider's own, in the
        /// variant of its position in the registry.
        #[derive(Copy, Clone, Debug)]
        pub enum HostRecip {
            $(
                #[allow(missing_docs)]
                $S(<$D as Divide>::Recip),
            )*
        }

        impl Divide for HostDivide {
            const NAME: &'static str = "host";
            type Recip = HostRecip;
            #[inline]
            fn recip(k: u32) -> HostRecip {
                at_index!(selected().divide.index(), [$(($S, $D))*], D => D::recip(k), in HostRecip)
            }
            #[inline]
            fn div(n: i32, r: &HostRecip) -> i32 {
                match r {
                    $(HostRecip::$S(x) => <$D>::div(n, x),)*
                }
            }
            fn max_error(n_max: u32, k_max: u32) -> u32 {
                at_index!(selected().divide.index(), [$(($S, $D))*], D => D::max_error(n_max, k_max))
            }
            fn mantissa_bits() -> u32 {
                at_index!(selected().divide.index(), [$(($S, $D))*], D => D::mantissa_bits())
            }
            #[inline]
            fn is_exact() -> bool {
                selected().divide == DivideName::EXACT
            }
        }
    };
}

/// The divider selected by [`with_selection`] (see the module docs).
#[derive(Copy, Clone, Debug, Default)]
pub struct HostDivide;

fixshade::for_each_divider!(dividers);

// ---------------------------------------------------------------------------------
// Specular models.

/// The registry's specular models, first with the exact divider, then dividing
/// with [`HostDivide`] (for [`with_slots`]).
macro_rules! speculars {
    ([] $(($name:expr, $Sp:ty)),* $(,)?) => {
        fixshade::for_each_specular! { speculars_divided[$($Sp,)*]; HostDivide }
    };
}

macro_rules! speculars_divided {
    ([$($Sp:ty,)*] $(($name:expr, $Spd:ty)),* $(,)?) => {
        with_slots! { host_specular [] $($Sp,)* $($Spd),* }
    };
}

/// [`HostSpecular`] and its [`HostParams`] over `(slot, model)` pairs.
macro_rules! host_specular {
    ($(($S:ident, $Sp:ty))*) => {
        /// Parameters of [`HostSpecular`]: the selected model's own, in the variant
        /// of its position (models dividing with [`HostDivide`] after the others).
        #[derive(Copy, Clone, Debug)]
        pub enum HostParams {
            $(
                #[allow(missing_docs)]
                $S(<$Sp as Specular>::Params),
            )*
        }

        impl Specular for HostSpecular {
            type Params = HostParams;
            fn prepare(n: Q16_16) -> HostParams {
                let Selection { divide, specular, .. } = selected();
                let models = SpecularName::NAMES.len();
                let i = specular.index() + if divide == DivideName::EXACT { 0 } else { models };
                at_index!(i, [$(($S, $Sp))*], Sp => Sp::prepare(n), in HostParams)
            }
            #[inline]
            fn eval(p: &HostParams, c: i32) -> i32 {
                match p {
                    $(HostParams::$S(x) => <$Sp>::eval(x, c),)*
                }
            }
            #[inline]
            fn eval_wide(p: &HostParams, c: i32) -> u64 {
                match p {
                    $(HostParams::$S(x) => <$Sp>::eval_wide(x, c),)*
                }
            }
            #[inline]
            fn enabled() -> bool {
                selected().specular_term
            }
            #[inline]
            fn two_sided() -> bool {
                selected().two_sided
            }
        }
    };
}

/// The specular model selected by [`with_selection`], dividing (Schlick's two) with
/// the selected divider, with or without the specular term and lighting one- or
/// two-sided as selected (see the module docs).
#[derive(Copy, Clone, Debug, Default)]
pub struct HostSpecular;

fixshade::for_each_specular!(speculars);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::desc::Named;
    use fixshade::divide::wide_recip;

    /// The selection of a divider and a model by name, one-sided.
    fn sel(divide: &str, specular: &str) -> Selection {
        Selection {
            divide: DivideName::named(divide),
            specular: SpecularName::named(specular),
            ..Selection::EXACT
        }
    }

    /// The specular term and two-sided lighting are the selection's, and on and
    /// one-sided outside it.
    #[test]
    fn host_specular_term_and_sides_are_selected() {
        assert!(HostSpecular::enabled() && !HostSpecular::two_sided());
        let two = Selection {
            two_sided: true,
            ..Selection::EXACT
        };
        assert!(with_selection(two, HostSpecular::two_sided));
        assert!(with_selection(two, HostSpecular::enabled));
        let diffuse = Selection {
            specular_term: false,
            ..Selection::EXACT
        };
        assert!(!with_selection(diffuse, HostSpecular::enabled));
        assert!(!with_selection(diffuse, HostSpecular::two_sided));
        assert!(HostSpecular::enabled() && !HostSpecular::two_sided());
    }

    /// Every selection gives exactly the core variant's quotients and reciprocals.
    #[test]
    fn host_divide_forwards_to_the_core_variant() {
        macro_rules! check_all {
            ([] $($D:ty),* $(,)?) => {$(
                with_selection(sel(<$D>::NAME, "exact"), || {
                    for k in [1u32, 2, 7, 13, 255, 1000, 4096] {
                        for n in [0i32, 1, -1, 255 << 16, -(200 << 16), i32::MAX, i32::MIN] {
                            assert_eq!(
                                HostDivide::div(n, &HostDivide::recip(k)),
                                <$D>::div(n, &<$D>::recip(k)),
                                "{} n={n} k={k}", <$D>::NAME
                            );
                        }
                    }
                    for d in [1u128, 5, 4095, 1 << 20, 123_456_789, 1 << 55] {
                        assert_eq!(wide_recip::<HostDivide>(d), wide_recip::<$D>(d));
                    }
                    assert_eq!(
                        HostDivide::max_error(255 << 16, 64),
                        <$D>::max_error(255 << 16, 64)
                    );
                });
            )*};
        }
        fixshade::for_each_divider!(check_all);
    }

    /// Every selection gives exactly the core model's values, with the exact
    /// divider and with an approximate one.
    #[test]
    fn host_specular_forwards_to_the_core_model() {
        macro_rules! check_all {
            ([$div:expr] $(($name:expr, $Sp:ty)),* $(,)?) => {$(
                with_selection(sel($div, $name), || {
                    for n in [1, 2, 24, 1000] {
                        let (a, b) = (HostSpecular::prepare(Q16_16::from_int(n)), <$Sp>::prepare(Q16_16::from_int(n)));
                        for c in [1, 1 << 20, 1 << 29, (1 << 30) - 7, 1 << 30] {
                            assert_eq!(HostSpecular::eval(&a, c), <$Sp>::eval(&b, c), "{} n={n}", $name);
                            assert_eq!(HostSpecular::eval_wide(&a, c), <$Sp>::eval_wide(&b, c));
                        }
                    }
                });
            )*};
        }
        fixshade::for_each_specular!(check_all["exact"]);
        fixshade::for_each_specular!(check_all["shift-add-6"]; fixshade::divide::ShiftAdd<6>);
        // The selection is restored.
        assert_eq!(selected(), Selection::EXACT);
        assert_eq!(SpecularName::ALL.len(), fixshade::specular::NAMES.len());
    }
}
