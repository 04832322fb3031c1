//! Numbers as a person reads them, in `check`'s summary and in scene errors.
//!
//! Rust's `{}` for an `f64` never uses an exponent, so `1e-308` prints as 307 zeros and
//! a one, and `1e300` as 301 digits. [`Readable`] prints the same shortest digits that
//! parse back to the same `f64`, in positional form between 1e-4 and 1e16 (as `0.01`,
//! `25`, `12345.5`) and in exponent form outside it (as `1e-308`, `2.5e20`), the rule
//! Python's `repr` follows. Counts are integers and print as they are.

use std::fmt;

/// An `f64` that displays in the shortest form that reads back to the same bits, with an
/// exponent only when the positional form would be long: `0.01`, `1e-308`, `2.5e20`.
///
/// ```
/// use physframes::numbers::Readable;
/// assert_eq!(Readable(0.01).to_string(), "0.01");
/// assert_eq!(Readable(1e-308).to_string(), "1e-308");
/// assert_eq!(Readable(-2.5e20).to_string(), "-2.5e20");
/// assert_eq!(Readable(30.0).to_string(), "30");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Readable(pub f64);

/// The smallest magnitude printed without an exponent.
const POSITIONAL_FROM: f64 = 1e-4;
/// The magnitude from which an exponent is used: 17 digits and more before the point.
const POSITIONAL_BELOW: f64 = 1e16;

impl fmt::Display for Readable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        let magnitude = x.abs();
        // Zero, infinities and NaN have no long positional form.
        if x == 0.0 || !x.is_finite() || (POSITIONAL_FROM..POSITIONAL_BELOW).contains(&magnitude) {
            write!(f, "{x}")
        } else {
            // `{:e}` writes the shortest round-trip digits with an exponent.
            write!(f, "{x:e}")
        }
    }
}

/// Returns `x` in its [`Readable`] form.
pub fn readable(x: f64) -> String {
    Readable(x).to_string()
}

/// Returns `x` rounded to three significant digits, in its [`Readable`] form: for
/// numbers that are only estimates, or too large to be exact (`4e306`, not
/// `4.000000000000001e306`).
pub fn about(x: f64) -> String {
    // `{:.2e}` rounds to three significant digits; read back, the shortest form of the
    // rounded number drops the zeros that are not needed.
    let rounded = format!("{x:.2e}").parse::<f64>().unwrap_or(x);
    Readable(rounded).to_string()
}

#[cfg(test)]
mod tests {
    use super::{about, readable};

    #[test]
    fn numbers_read_back_to_the_same_bits_and_stay_short() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.01,
            1.0 / 30.0,
            1e-4,
            9.99e-5,
            1e15,
            1e16,
            123456789.125,
            1e-308,
            5e-324,
            f64::MAX,
            -f64::MIN_POSITIVE,
            0.1 + 0.2,
        ] {
            let text = readable(x);
            assert_eq!(
                text.parse::<f64>().map(f64::to_bits),
                Ok(x.to_bits()),
                "{text}"
            );
            assert!(text.len() <= 24, "{x:?} printed as {text}");
        }
    }

    #[test]
    fn the_exponent_appears_only_outside_the_positional_range() {
        assert_eq!(readable(1e-308), "1e-308");
        assert_eq!(readable(1e-300), "1e-300");
        assert_eq!(readable(9.99e-5), "9.99e-5");
        assert_eq!(readable(1e-4), "0.0001");
        assert_eq!(readable(0.04), "0.04");
        assert_eq!(readable(5.0), "5");
        assert_eq!(readable(9999999999999998.0), "9999999999999998");
        assert_eq!(readable(1e16), "1e16");
        assert_eq!(readable(-3.5e300), "-3.5e300");
        assert_eq!(readable(f64::INFINITY), "inf");
        assert_eq!(readable(f64::NAN), "NaN");
    }

    #[test]
    fn estimates_keep_three_significant_digits() {
        assert_eq!(about(4.000000000000001e306), "4e306");
        assert_eq!(about(4.440892098500626e-18), "4.44e-18");
        assert_eq!(about(123456.0), "123000");
        assert_eq!(about(0.0), "0");
        assert_eq!(about(f64::INFINITY), "inf");
    }
}
