//! The divider chosen on the command line or in a scene file, as one type.
//!
//! The core takes its divider as a type (`Classic<ShiftAdd<8>>`,
//! `WithDivide<Gradient, Table>`, `Schlick<ShiftAddRounded<12>>`), which a firmware
//! names once. The simulator offers 27 approximate dividers on top of every span
//! method, specular model and pixel format; monomorphising the pipeline for each
//! would multiply its build time by 28. So the host draws the approximate dividers
//! through one type, [`HostDivide`], whose `recip` and `div` forward to the core's
//! variant selected for the current thread ([`select`]): the results are exactly
//! the core variant's; only the host's timing includes one predictable branch per
//! division. `exact` never goes through it: the pipeline then draws the plain types,
//! bit-identical to the pipeline before the seam.

use std::cell::Cell;

use fixshade::divide::{Divide, Exact, ShiftAdd, ShiftAddRounded, Table, TableRecip};

use crate::desc::DivideName;

thread_local! {
    static SELECTED: Cell<DivideName> = const { Cell::new(DivideName::Table) };
}

/// Selects the variant [`HostDivide`] forwards to on this thread.
pub fn select(d: DivideName) {
    SELECTED.with(|s| s.set(d));
}

/// The divider selected by [`select`] (see the module docs).
#[derive(Copy, Clone, Debug, Default)]
pub struct HostDivide;

/// Prepared divisor of [`HostDivide`]: the selected variant's own.
#[derive(Copy, Clone, Debug)]
pub enum HostRecip {
    /// [`Exact`]'s clamped divisor.
    Exact(u32),
    /// [`Table`]'s entry.
    Table(TableRecip),
    /// A shift-and-add mask and its `N`.
    Mask(u32, u8),
}

macro_rules! by_n {
    ($n:expr, $T:ident, $f:ident ( $($a:expr),* )) => {
        match $n {
            4 => $T::<4>::$f($($a),*),
            5 => $T::<5>::$f($($a),*),
            6 => $T::<6>::$f($($a),*),
            7 => $T::<7>::$f($($a),*),
            8 => $T::<8>::$f($($a),*),
            9 => $T::<9>::$f($($a),*),
            10 => $T::<10>::$f($($a),*),
            11 => $T::<11>::$f($($a),*),
            12 => $T::<12>::$f($($a),*),
            13 => $T::<13>::$f($($a),*),
            14 => $T::<14>::$f($($a),*),
            15 => $T::<15>::$f($($a),*),
            _ => $T::<16>::$f($($a),*),
        }
    };
}

impl Divide for HostDivide {
    const NAME: &'static str = "host";
    type Recip = HostRecip;
    #[inline]
    fn recip(k: u32) -> HostRecip {
        match SELECTED.with(Cell::get) {
            DivideName::Exact => HostRecip::Exact(Exact::recip(k)),
            DivideName::Table => HostRecip::Table(Table::recip(k)),
            DivideName::ShiftAdd(n) => HostRecip::Mask(by_n!(n, ShiftAdd, recip(k)), n),
            DivideName::ShiftAddRounded(n) => {
                HostRecip::Mask(by_n!(n, ShiftAddRounded, recip(k)), n)
            }
        }
    }
    #[inline]
    fn div(n: i32, r: &HostRecip) -> i32 {
        // The truncated and rounded variants share `div`; they differ in the mask.
        match *r {
            HostRecip::Exact(k) => Exact::div(n, &k),
            HostRecip::Table(t) => Table::div(n, &t),
            HostRecip::Mask(m, bits) => by_n!(bits, ShiftAdd, div(n, &m)),
        }
    }
    fn max_error(n_max: u32, k_max: u32) -> u32 {
        match SELECTED.with(Cell::get) {
            DivideName::Exact => Exact::max_error(n_max, k_max),
            DivideName::Table => Table::max_error(n_max, k_max),
            DivideName::ShiftAdd(n) => by_n!(n, ShiftAdd, max_error(n_max, k_max)),
            DivideName::ShiftAddRounded(n) => by_n!(n, ShiftAddRounded, max_error(n_max, k_max)),
        }
    }
    fn mantissa_bits() -> u32 {
        match SELECTED.with(Cell::get) {
            DivideName::Exact => <Exact as Divide>::mantissa_bits(),
            DivideName::Table => <Table as Divide>::mantissa_bits(),
            DivideName::ShiftAdd(n) => by_n!(n, ShiftAdd, mantissa_bits()),
            DivideName::ShiftAddRounded(n) => by_n!(n, ShiftAddRounded, mantissa_bits()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fixshade::divide::wide_recip;

    /// Every selection gives exactly the core variant's quotients and reciprocals.
    #[test]
    fn forwards_to_the_core_variant() {
        fn check<D: Divide>(name: DivideName) {
            select(name);
            for k in [1u32, 2, 7, 13, 255, 1000, 4096] {
                for n in [0i32, 1, -1, 255 << 16, -(200 << 16), i32::MAX, i32::MIN] {
                    assert_eq!(
                        HostDivide::div(n, &HostDivide::recip(k)),
                        D::div(n, &D::recip(k)),
                        "{name:?} n={n} k={k}"
                    );
                }
            }
            for d in [1u128, 5, 4095, 1 << 20, 123_456_789, 1 << 55] {
                assert_eq!(wide_recip::<HostDivide>(d), wide_recip::<D>(d), "{name:?}");
            }
            assert_eq!(
                HostDivide::max_error(255 << 16, 64),
                D::max_error(255 << 16, 64)
            );
        }
        check::<Table>(DivideName::Table);
        check::<Exact>(DivideName::Exact);
        check::<ShiftAdd<4>>(DivideName::ShiftAdd(4));
        check::<ShiftAdd<9>>(DivideName::ShiftAdd(9));
        check::<ShiftAdd<16>>(DivideName::ShiftAdd(16));
        check::<ShiftAddRounded<5>>(DivideName::ShiftAddRounded(5));
        check::<ShiftAddRounded<16>>(DivideName::ShiftAddRounded(16));
    }
}
