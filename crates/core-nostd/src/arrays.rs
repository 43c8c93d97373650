//! Small fixed-size arrays built element by element.
//!
//! `core::array::from_fn` and `<[T; N]>::map` go through the standard library's
//! fallible array builder (a drop guard and a `try` adapter around every call). After
//! optimisation both compile to the same few instructions as the loops below, but
//! before it every generic function that uses them carries that machinery once per
//! instantiation, and the host simulator instantiates the pixel path for every span
//! method, depth mode, shading and pixel format. These two functions give the same
//! arrays with a plain loop, which the compiler reads in a fraction of the time.
//! Firmware (`target_os = "none"`) keeps the standard library's functions: its
//! images are monomorphised for one configuration, and the size-optimised ones
//! would grow with a loop copied into every caller.
//!
//! Both take `Copy` elements (every array the core builds this way holds numbers,
//! vertices or references) and arrays of at least one element.

/// `[f(0), f(1), …, f(N - 1)]`, calling `f` once per index, in order.
#[cfg(not(target_os = "none"))]
#[inline(always)]
pub(crate) fn from_fn<T: Copy, const N: usize>(mut f: impl FnMut(usize) -> T) -> [T; N] {
    const { assert!(N > 0, "arrays::from_fn builds non-empty arrays") };
    let mut out = [f(0); N];
    let mut k = 1;
    while k < N {
        out[k] = f(k);
        k += 1;
    }
    out
}

/// `[f(a[0]), f(a[1]), …]`, calling `f` once per element, in order.
#[cfg(not(target_os = "none"))]
#[inline(always)]
pub(crate) fn map<T: Copy, U: Copy, const N: usize>(
    a: [T; N],
    mut f: impl FnMut(T) -> U,
) -> [U; N] {
    const { assert!(N > 0, "arrays::map maps non-empty arrays") };
    let mut out = [f(a[0]); N];
    let mut k = 1;
    while k < N {
        out[k] = f(a[k]);
        k += 1;
    }
    out
}

/// On the chips: `core::array::from_fn` itself, so the firmware's code is the
/// standard library's (`#[inline(always)]` loops would be copied into every caller
/// of an image built for size).
#[cfg(target_os = "none")]
#[inline(always)]
pub(crate) fn from_fn<T: Copy, const N: usize>(f: impl FnMut(usize) -> T) -> [T; N] {
    core::array::from_fn(f)
}

/// On the chips: `<[T; N]>::map` itself (see [`from_fn`]).
#[cfg(target_os = "none")]
#[inline(always)]
pub(crate) fn map<T: Copy, U: Copy, const N: usize>(a: [T; N], f: impl FnMut(T) -> U) -> [U; N] {
    a.map(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_arrays_as_core() {
        let mut calls = [0usize; 4];
        let mut n = 0;
        let a: [usize; 4] = from_fn(|k| {
            calls[n] = k;
            n += 1;
            k * k + 1
        });
        assert_eq!(a, core::array::from_fn::<usize, 4, _>(|k| k * k + 1));
        assert_eq!(calls, [0, 1, 2, 3], "called once per index, in order");
        assert_eq!(map([3i32, -1, 7], |x| x * 2), [3i32, -1, 7].map(|x| x * 2));
        assert_eq!(map([5u8], |x| x as u32 + 1), [6u32]);
    }
}
