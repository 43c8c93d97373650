//! Fixed-point number types. The format is in the name: `Q16_16` has 16 integer
//! bits (sign included) and 16 fraction bits.
//!
//! Overflow behaviour is spelled out per operation: the arithmetic operators of
//! these types saturate (a model coordinate that overflows must not wrap to the other
//! side of the world); the raster stage, which works on raw integers, documents its
//! own wrapping arithmetic where it relies on it.
//!
//! With the feature `fixed`, each type converts losslessly to and from its
//! counterpart in the [`fixed`](https://docs.rs/fixed) crate (`Q16_16` ↔ `I16F16`,
//! `Q2_14` ↔ `I2F14`, `Angle` ↔ `U0F32` turns; `From` both ways, the same bits).
//! With `f32-input`, `f32` values convert by their bits (`Q16_16::from_f32`,
//! `Q2_14::from_f32`); no float function is needed at that boundary (degrees go
//! through `Angle::from_degrees_q16`, normals are normalised by the core in
//! integers), so the crate has no `micromath` dependency.
//!
//! ```
//! use fixshade::fixed::Q16_16;
//! let a = Q16_16::from_ratio(3, 2); // 1.5
//! let b = Q16_16::from_int(2);
//! assert_eq!((a * b).to_bits(), 3 << 16);
//! assert_eq!(Q16_16::from_bits(1 << 16) / b, Q16_16::from_ratio(1, 2));
//! ```

use core::ops::{Add, Div, Mul, Neg, Sub};

/// Signed fixed point with 16 integer and 16 fraction bits in an `i32`
/// (range about ±32768, resolution 2⁻¹⁶ ≈ 1.5e-5).
///
/// Used for model coordinates, colours (0..=1), shininess and attenuation factors.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// let x = Q16_16::from_ratio(-5, 4); // -1.25
/// assert_eq!(x.floor_int(), -2);
/// assert_eq!(x.abs(), Q16_16::from_ratio(5, 4));
/// assert_eq!(x.clamp(Q16_16::ZERO, Q16_16::ONE), Q16_16::ZERO);
/// // Operators saturate instead of wrapping.
/// assert_eq!(Q16_16::MAX + Q16_16::ONE, Q16_16::MAX);
/// assert_eq!(x.to_string(), "-1.25000");
/// ```
#[allow(non_camel_case_types)]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Q16_16(i32);

impl Q16_16 {
    /// Number of fraction bits.
    pub const FRAC_BITS: u32 = 16;
    /// 0.
    pub const ZERO: Q16_16 = Q16_16(0);
    /// 1.
    pub const ONE: Q16_16 = Q16_16(1 << 16);
    /// The largest value, just below 32768.
    pub const MAX: Q16_16 = Q16_16(i32::MAX);
    /// The smallest value, -32768.
    pub const MIN: Q16_16 = Q16_16(i32::MIN);

    /// The value whose raw bits are `bits` (value = bits / 65536).
    pub const fn from_bits(bits: i32) -> Q16_16 {
        Q16_16(bits)
    }

    /// The raw bits.
    pub const fn to_bits(self) -> i32 {
        self.0
    }

    /// An integer, saturating outside ±32767.
    ///
    /// ```
    /// # use fixshade::fixed::Q16_16;
    /// assert_eq!(Q16_16::from_int(-3).to_bits(), -3 * 65536);
    /// assert_eq!(Q16_16::from_int(40_000), Q16_16::MAX);
    /// ```
    pub const fn from_int(v: i32) -> Q16_16 {
        Q16_16(sat_i64_to_i32((v as i64) << 16))
    }

    /// `num / den` rounded to nearest (ties away from zero), saturating; `den == 0`
    /// gives zero.
    ///
    /// ```
    /// # use fixshade::fixed::Q16_16;
    /// assert_eq!(Q16_16::from_ratio(1, 3).to_bits(), 21845);
    /// assert_eq!(Q16_16::from_ratio(-1, 3).to_bits(), -21845);
    /// ```
    pub const fn from_ratio(num: i32, den: i32) -> Q16_16 {
        if den == 0 {
            return Q16_16(0);
        }
        Q16_16(sat_i64_to_i32(div_round_i64(
            (num as i64) << 16,
            den as i64,
        )))
    }

    /// The value rounded down to an integer.
    pub const fn floor_int(self) -> i32 {
        self.0 >> 16
    }

    /// Absolute value, saturating at `MAX`.
    pub const fn abs(self) -> Q16_16 {
        Q16_16(self.0.saturating_abs())
    }

    /// The smaller of two values.
    pub const fn min(self, o: Q16_16) -> Q16_16 {
        if self.0 < o.0 {
            self
        } else {
            o
        }
    }

    /// The larger of two values.
    pub const fn max(self, o: Q16_16) -> Q16_16 {
        if self.0 > o.0 {
            self
        } else {
            o
        }
    }

    /// Clamps to `[lo, hi]`.
    pub const fn clamp(self, lo: Q16_16, hi: Q16_16) -> Q16_16 {
        self.max(lo).min(hi)
    }
}

impl Add for Q16_16 {
    type Output = Q16_16;
    /// Saturating addition.
    fn add(self, o: Q16_16) -> Q16_16 {
        Q16_16(self.0.saturating_add(o.0))
    }
}

impl Sub for Q16_16 {
    type Output = Q16_16;
    /// Saturating subtraction.
    fn sub(self, o: Q16_16) -> Q16_16 {
        Q16_16(self.0.saturating_sub(o.0))
    }
}

impl Neg for Q16_16 {
    type Output = Q16_16;
    /// Saturating negation.
    fn neg(self) -> Q16_16 {
        Q16_16(self.0.saturating_neg())
    }
}

impl Mul for Q16_16 {
    type Output = Q16_16;
    /// Product rounded to nearest, saturating. The i64 product of two i32 cannot
    /// overflow (|a·b| ≤ 2⁶²).
    fn mul(self, o: Q16_16) -> Q16_16 {
        let p = self.0 as i64 * o.0 as i64;
        Q16_16(sat_i64_to_i32((p + (1 << 15)) >> 16))
    }
}

impl Div for Q16_16 {
    type Output = Q16_16;
    /// Quotient rounded to nearest, saturating; division by zero saturates to
    /// `MAX`/`MIN` by the sign of the dividend (zero for 0/0).
    fn div(self, o: Q16_16) -> Q16_16 {
        if o.0 == 0 {
            return match self.0 {
                0 => Q16_16::ZERO,
                v if v > 0 => Q16_16::MAX,
                _ => Q16_16::MIN,
            };
        }
        // |self << 16| ≤ 2⁴⁷: fits i64.
        Q16_16(sat_i64_to_i32(div_round_i64(
            (self.0 as i64) << 16,
            o.0 as i64,
        )))
    }
}

impl core::fmt::Display for Q16_16 {
    /// Prints the exact decimal value to 5 places (e.g. `-1.50000`), no floats involved.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let v = self.0 as i64;
        let sign = if v < 0 { "-" } else { "" };
        let a = v.unsigned_abs();
        let int = a >> 16;
        let frac = ((a & 0xFFFF) * 100_000 + (1 << 15)) >> 16;
        let (int, frac) = if frac >= 100_000 {
            (int + 1, frac - 100_000)
        } else {
            (int, frac)
        };
        write!(f, "{sign}{int}.{frac:05}")
    }
}

/// Signed fixed point with 2 integer and 14 fraction bits in an `i16`: unit normal
/// components (range [-2, 2), resolution 2⁻¹⁴ ≈ 6.1e-5).
///
/// ```
/// use fixshade::fixed::Q2_14;
/// let half = Q2_14::from_bits(1 << 13);
/// assert_eq!(half.to_bits() * 2, Q2_14::ONE.to_bits());
/// ```
#[allow(non_camel_case_types)]
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct Q2_14(i16);

impl Q2_14 {
    /// 1.
    pub const ONE: Q2_14 = Q2_14(1 << 14);
    /// The value with raw bits `bits` (value = bits / 16384).
    pub const fn from_bits(bits: i16) -> Q2_14 {
        Q2_14(bits)
    }
    /// The raw bits.
    pub const fn to_bits(self) -> i16 {
        self.0
    }
}

/// An angle as a binary fraction of a full turn: `Angle(1 << 30)` is 90°, and the
/// wrap-around of `u32` is the wrap-around of the circle, so rotation by repeated
/// addition never drifts.
///
/// ```
/// # use fixshade::fixed::Angle;
/// assert_eq!(Angle::from_degrees(90), Angle::from_turns_bits(1 << 30));
/// assert_eq!(Angle::from_degrees(-90), Angle::from_degrees(270));
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct Angle(u32);

impl Angle {
    /// An angle of `bits / 2³²` turns.
    pub const fn from_turns_bits(bits: u32) -> Angle {
        Angle(bits)
    }

    /// The raw turn fraction.
    pub const fn to_turns_bits(self) -> u32 {
        self.0
    }

    /// A whole number of degrees (any sign), rounded to the nearest 2⁻³² turn.
    pub const fn from_degrees(deg: i32) -> Angle {
        Angle::from_degrees_q16(Q16_16::from_int(deg.rem_euclid(360)))
    }

    /// Degrees in Q16.16, rounded to the nearest 2⁻³² turn.
    pub const fn from_degrees_q16(deg: Q16_16) -> Angle {
        // turns = deg / 360; bits = deg_raw * 2^32 / (360 * 2^16) = deg_raw * 2^16 / 360.
        let bits = div_round_i64((deg.0 as i64) << 16, 360);
        Angle(bits as u32) // wraps modulo one turn, which is the intended meaning
    }

    /// Sum modulo one turn.
    pub const fn wrapping_add(self, o: Angle) -> Angle {
        Angle(self.0.wrapping_add(o.0))
    }

    /// Half the angle (for angles below one turn).
    pub const fn half(self) -> Angle {
        Angle(self.0 >> 1)
    }
}

/// Rounds `num / den` to nearest, ties away from zero. `den` must not be 0.
pub(crate) const fn div_round_i64(num: i64, den: i64) -> i64 {
    let (n, d) = if den < 0 { (-num, -den) } else { (num, den) };
    if n >= 0 {
        (n + d / 2) / d
    } else {
        -((-n + d / 2) / d)
    }
}

/// Saturates an i64 into the i32 range.
pub(crate) const fn sat_i64_to_i32(v: i64) -> i32 {
    if v > i32::MAX as i64 {
        i32::MAX
    } else if v < i32::MIN as i64 {
        i32::MIN
    } else {
        v as i32
    }
}

/// Error converting a value into a fixed-point format.
///
/// ```
/// use fixshade::fixed::NumError;
/// assert_eq!(NumError::OutOfRange.to_string(), "value is outside the fixed-point range");
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum NumError {
    /// The input was NaN or infinite.
    NotFinite,
    /// The input is outside the range of the target format.
    OutOfRange,
}

impl core::fmt::Display for NumError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            NumError::NotFinite => "value is NaN or infinite",
            NumError::OutOfRange => "value is outside the fixed-point range",
        })
    }
}

#[cfg(feature = "f32-input")]
mod f32_input {
    //! The optional f32 input boundary. Conversion reads the IEEE-754 bits; there is
    //! no float arithmetic.
    use super::{NumError, Q16_16, Q2_14};

    /// `x · 2^frac` rounded to nearest (ties away from zero) as i64, from the bits
    /// of `x`; `None` if it needs more than 62 bits.
    fn scaled(x: f32, frac: i32) -> Result<i64, NumError> {
        let bits = x.to_bits();
        let exp = ((bits >> 23) & 0xFF) as i32;
        if exp == 0xFF {
            return Err(NumError::NotFinite);
        }
        let mant = if exp == 0 {
            (bits & 0x7F_FFFF) as i64
        } else {
            ((bits & 0x7F_FFFF) | 0x80_0000) as i64
        };
        // value = mant · 2^(exp - 150) (exp 0: 2^-149).
        let e = if exp == 0 { -149 } else { exp - 150 } + frac;
        let mag = if e >= 0 {
            if e > 38 {
                return Err(NumError::OutOfRange);
            }
            mant << e
        } else if e < -40 {
            0
        } else {
            let s = -e;
            (mant + (1 << (s - 1))) >> s
        };
        Ok(if bits >> 31 == 1 { -mag } else { mag })
    }

    impl Q16_16 {
        /// Converts an `f32`, rounding to nearest.
        ///
        /// ```
        /// # use fixshade::fixed::{Q16_16, NumError};
        /// assert_eq!(Q16_16::from_f32(1.5), Ok(Q16_16::from_ratio(3, 2)));
        /// assert_eq!(Q16_16::from_f32(f32::NAN), Err(NumError::NotFinite));
        /// assert_eq!(Q16_16::from_f32(1e9), Err(NumError::OutOfRange));
        /// ```
        pub fn from_f32(x: f32) -> Result<Q16_16, NumError> {
            let v = scaled(x, 16)?;
            i32::try_from(v)
                .map(Q16_16)
                .map_err(|_| NumError::OutOfRange)
        }
    }

    impl Q2_14 {
        /// Converts an `f32` normal component in [-2, 2), rounding to nearest.
        pub fn from_f32(x: f32) -> Result<Q2_14, NumError> {
            let v = scaled(x, 14)?;
            i16::try_from(v)
                .map(Q2_14)
                .map_err(|_| NumError::OutOfRange)
        }
    }
}

/// Conversions to and from the [`fixed`](https://docs.rs/fixed) crate's types
/// (feature `fixed`): each pair has the same bits, so the conversions are lossless
/// and free. A firmware that keeps its model or its angles in `fixed` types hands
/// them over as they are.
///
/// ```
/// use fixed::types::{I16F16, I2F14, U0F32};
/// use fixshade::fixed::{Angle, Q16_16, Q2_14};
/// let x = I16F16::from_num(-1.25);
/// let q: Q16_16 = x.into();
/// assert_eq!(q, Q16_16::from_ratio(-5, 4));
/// assert_eq!(I16F16::from(q), x);
/// let n: Q2_14 = I2F14::from_num(0.5).into();
/// assert_eq!(n.to_bits(), 1 << 13);
/// assert_eq!(I2F14::from(Q2_14::ONE), I2F14::ONE);
/// // An angle is a fraction of a turn: a quarter turn is 90°.
/// let a: Angle = U0F32::from_num(0.25).into();
/// assert_eq!(a, Angle::from_degrees(90));
/// assert_eq!(U0F32::from(Angle::from_degrees(180)), U0F32::from_num(0.5));
/// ```
#[cfg(feature = "fixed")]
mod fixed_crate {
    use super::{Angle, Q16_16, Q2_14};
    use ::fixed::types::{I16F16, I2F14, U0F32};

    impl From<I16F16> for Q16_16 {
        fn from(v: I16F16) -> Q16_16 {
            Q16_16::from_bits(v.to_bits())
        }
    }

    impl From<Q16_16> for I16F16 {
        fn from(v: Q16_16) -> I16F16 {
            I16F16::from_bits(v.to_bits())
        }
    }

    impl From<I2F14> for Q2_14 {
        fn from(v: I2F14) -> Q2_14 {
            Q2_14::from_bits(v.to_bits())
        }
    }

    impl From<Q2_14> for I2F14 {
        fn from(v: Q2_14) -> I2F14 {
            I2F14::from_bits(v.to_bits())
        }
    }

    impl From<U0F32> for Angle {
        fn from(v: U0F32) -> Angle {
            Angle::from_turns_bits(v.to_bits())
        }
    }

    impl From<Angle> for U0F32 {
        fn from(v: Angle) -> U0F32 {
            U0F32::from_bits(v.to_turns_bits())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mul_and_div_round_to_nearest() {
        let third = Q16_16::from_ratio(1, 3);
        assert_eq!((third * Q16_16::from_int(3)).to_bits(), 65535);
        assert_eq!(Q16_16::from_int(1) / Q16_16::from_int(3), third);
        assert_eq!(Q16_16::from_int(1) / Q16_16::ZERO, Q16_16::MAX);
        assert_eq!(Q16_16::from_int(-1) / Q16_16::ZERO, Q16_16::MIN);
        assert_eq!(Q16_16::MAX * Q16_16::from_int(2), Q16_16::MAX);
    }

    #[test]
    fn angle_from_degrees() {
        assert_eq!(Angle::from_degrees(45).to_turns_bits(), 1 << 29);
        assert_eq!(Angle::from_degrees(360).to_turns_bits(), 0);
        assert_eq!(
            Angle::from_degrees_q16(Q16_16::from_ratio(45, 2)).to_turns_bits(),
            1 << 28
        );
    }

    #[test]
    fn display_is_exact_decimal() {
        extern crate std;
        use std::string::ToString;
        assert_eq!(Q16_16::from_ratio(-3, 2).to_string(), "-1.50000");
        assert_eq!(Q16_16::from_bits(65535).to_string(), "0.99998");
    }
}
