//! Tick positions and tick labels for linear and base-10 logarithmic axes.
//!
//! Linear axes get "nice" steps of 1, 2 or 5 times a power of ten: the smallest such step
//! that puts at most about `target` intervals across the range (the step rule of Heckbert's
//! "Nice numbers for graph labels", Graphics Gems, 1990, applied to a fixed range, so every
//! tick lies inside the range and is a whole multiple of the step). Tick values are
//! computed as `i·m / 10^k` with integers `i·m`, one correctly rounded division, so `0.3`
//! is the double nearest 0.3 rather than `3 × 0.1`.
//!
//! Log axes get one major tick per decade (every n-th decade when there are too many),
//! with minor ticks at 2..9 times each power of ten. A range narrower than two decades
//! falls back to labelled 1-2-5 ticks.
//!
//! Labels use the true minus sign `−` (U+2212), never print `-0`, use one number of
//! decimals along an axis, and switch to `m×10ᵏ` for very large or very small values.

/// One labelled tick.
#[derive(Clone, Debug, PartialEq)]
pub struct Tick {
    /// Position in data units.
    pub value: f64,
    /// Text printed beside the tick.
    pub label: String,
}

/// All ticks of one axis, in increasing order of value.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct AxisTicks {
    /// Labelled ticks.
    pub major: Vec<Tick>,
    /// Shorter, unlabelled ticks.
    pub minor: Vec<f64>,
}

impl AxisTicks {
    /// The values of the major ticks.
    pub fn values(&self) -> Vec<f64> {
        self.major.iter().map(|t| t.value).collect()
    }

    /// The labels of the major ticks.
    pub fn labels(&self) -> Vec<&str> {
        self.major.iter().map(|t| t.label.as_str()).collect()
    }
}

/// How decade labels on a log axis are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LogLabelStyle {
    /// `10⁻⁶`, with superscript digits.
    #[default]
    Superscript,
    /// `1e-6`, the form a program would parse.
    ENotation,
}

/// A step of `mantissa × 10^exponent` with a mantissa of 1, 2 or 5.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NiceStep {
    /// 1, 2 or 5.
    pub mantissa: i64,
    /// The power of ten.
    pub exponent: i32,
}

impl NiceStep {
    /// The smallest 1-2-5 step that divides `span` into at most `target` intervals.
    /// Returns `None` when `span` is not finite and positive.
    pub fn for_span(span: f64, target: usize) -> Option<NiceStep> {
        if !(span.is_finite() && span > 0.0) {
            return None;
        }
        let raw = span / target.max(1) as f64;
        let mut exponent = raw.log10().floor() as i32;
        // Rounding in log10 may land one decade off; walk to the right decade exactly.
        while NiceStep::value_of(1, exponent) > raw {
            exponent -= 1;
        }
        while NiceStep::value_of(10, exponent) <= raw {
            exponent += 1;
        }
        for mantissa in [1, 2, 5, 10] {
            if NiceStep::value_of(mantissa, exponent) >= raw * (1.0 - 1e-9) {
                return Some(if mantissa == 10 {
                    NiceStep {
                        mantissa: 1,
                        exponent: exponent + 1,
                    }
                } else {
                    NiceStep { mantissa, exponent }
                });
            }
        }
        unreachable!("a mantissa of 10 always covers a raw step below 10^(exponent+1)")
    }

    /// The step in data units.
    pub fn value(&self) -> f64 {
        NiceStep::value_of(self.mantissa, self.exponent)
    }

    /// The `i`-th multiple of the step, computed with one rounding.
    pub fn multiple(&self, i: i64) -> f64 {
        NiceStep::value_of(i * self.mantissa, self.exponent)
    }

    /// Digits after the decimal point needed to print every multiple of the step exactly.
    pub fn decimals(&self) -> usize {
        (-self.exponent).max(0) as usize
    }

    fn value_of(integer: i64, exponent: i32) -> f64 {
        pow10_scaled(integer as f64, exponent)
    }
}

/// Ticks for a linear axis over `[min, max]`, aiming at about `target` intervals.
///
/// Every tick lies inside the range (within a relative 1e-9 of a step at the ends) and
/// is a whole multiple of the step. A range of zero width gets one tick; a non-finite
/// range gets none.
pub fn linear_ticks(min: f64, max: f64, target: usize) -> AxisTicks {
    let (min, max) = if min <= max { (min, max) } else { (max, min) };
    if !(min.is_finite() && max.is_finite()) {
        return AxisTicks::default();
    }
    let Some(step) = NiceStep::for_span(max - min, target) else {
        return AxisTicks {
            major: vec![Tick {
                value: min,
                label: format_plain(min, decimals_for(min)),
            }],
            minor: Vec::new(),
        };
    };
    let s = step.value();
    let first = (min / s - 1e-9).ceil();
    let last = (max / s + 1e-9).floor();
    if !(first.abs() < 1e15 && last.abs() < 1e15) || last - first > 1000.0 {
        // The range is too far from zero for its width to be split into steps in f64.
        return AxisTicks::default();
    }
    let values: Vec<f64> = (first as i64..=last as i64)
        .map(|i| step.multiple(i))
        .collect();
    let labels = format_linear_labels(&values, step);
    AxisTicks {
        major: values
            .into_iter()
            .zip(labels)
            .map(|(value, label)| Tick { value, label })
            .collect(),
        minor: Vec::new(),
    }
}

/// Ticks for a base-10 log axis over `[min, max]` (both positive), with at most about
/// `target` labelled ticks.
pub fn log10_ticks(min: f64, max: f64, target: usize, style: LogLabelStyle) -> AxisTicks {
    let (min, max) = if min <= max { (min, max) } else { (max, min) };
    if !(min.is_finite() && max.is_finite() && min > 0.0) {
        return AxisTicks::default();
    }
    let lo = min.log10().floor() as i32 - 1;
    let hi = max.log10().ceil() as i32 + 1;
    let inside = |v: f64| v >= min * (1.0 - 1e-9) && v <= max * (1.0 + 1e-9);
    let decades: Vec<i32> = (lo..=hi).filter(|&k| inside(decade(1, k))).collect();
    if decades.len() >= 2 {
        let stride = decades.len().div_ceil(target.max(1)) as i32;
        let mut major = Vec::new();
        let mut minor = Vec::new();
        for k in lo..=hi {
            if inside(decade(1, k)) {
                if k.rem_euclid(stride) == 0 {
                    major.push(Tick {
                        value: decade(1, k),
                        label: format_decade(k, style),
                    });
                } else {
                    minor.push(decade(1, k));
                }
            }
            if stride == 1 {
                minor.extend((2..=9).map(|d| decade(d, k)).filter(|&v| inside(v)));
            }
        }
        minor.sort_by(f64::total_cmp);
        return AxisTicks { major, minor };
    }
    // Less than two decades: label 1-2-5 multiples, or failing that every multiple.
    for labelled in [&[1, 2, 5][..], &[1, 2, 3, 4, 5, 6, 7, 8, 9][..]] {
        let mut major = Vec::new();
        let mut minor = Vec::new();
        for k in lo..=hi {
            for d in 1..=9 {
                let v = decade(d, k);
                if !inside(v) {
                    continue;
                }
                if labelled.contains(&d) {
                    major.push(Tick {
                        value: v,
                        label: format_multiple_of_decade(d, k, style),
                    });
                } else {
                    minor.push(v);
                }
            }
        }
        if major.len() >= 2 {
            return AxisTicks { major, minor };
        }
    }
    linear_ticks(min, max, target)
}

/// Labels for linear tick values that are multiples of `step`: plain decimals with the
/// step's number of decimals, or `m×10ᵏ` when the values are very large or very small.
pub fn format_linear_labels(values: &[f64], step: NiceStep) -> Vec<String> {
    let biggest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if biggest >= 1e6 || (biggest > 0.0 && biggest < 1e-3) {
        let k = biggest.log10().floor() as i32;
        let decimals = (k - step.exponent).max(0) as usize;
        values
            .iter()
            .map(|&v| {
                if v == 0.0 {
                    "0".to_owned()
                } else {
                    let mantissa = pow10_scaled(v, -k);
                    format!(
                        "{}×10{}",
                        format_plain(mantissa, decimals),
                        superscript(&k.to_string())
                    )
                }
            })
            .collect()
    } else {
        values
            .iter()
            .map(|&v| format_plain(v, step.decimals()))
            .collect()
    }
}

/// Prints `value` with `decimals` digits after the point, the minus sign `−` for negative
/// values, and never a negative zero.
pub fn format_plain(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    if text.bytes().all(|b| matches!(b, b'-' | b'0' | b'.')) {
        // Every digit is zero: drop any sign so -0.001 printed to one decimal reads "0.0".
        return text.trim_start_matches('-').to_owned();
    }
    text.replace('-', "−")
}

/// The label of the decade `10^exponent`: `10⁻⁶` or `1e-6`.
pub fn format_decade(exponent: i32, style: LogLabelStyle) -> String {
    match style {
        LogLabelStyle::Superscript => format!("10{}", superscript(&exponent.to_string())),
        LogLabelStyle::ENotation => format!("1e{exponent}"),
    }
}

/// Replaces the digits, signs and parentheses in `text` with their superscript forms;
/// other characters are kept.
pub fn superscript(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            '9' => '⁹',
            '-' | '−' => '⁻',
            '+' => '⁺',
            '(' => '⁽',
            ')' => '⁾',
            other => other,
        })
        .collect()
}

/// The label of `digit × 10^exponent` on a narrow log axis.
fn format_multiple_of_decade(digit: i64, exponent: i32, style: LogLabelStyle) -> String {
    if (-3..=4).contains(&exponent) {
        let value = decade(digit, exponent);
        return format_plain(value, (-exponent).max(0) as usize);
    }
    match style {
        LogLabelStyle::Superscript if digit == 1 => format_decade(exponent, style),
        LogLabelStyle::Superscript => {
            format!("{digit}×10{}", superscript(&exponent.to_string()))
        }
        LogLabelStyle::ENotation => format!("{digit}e{exponent}"),
    }
}

/// The double nearest `digit × 10^exponent`, exactly as a decimal literal would parse.
fn decade(digit: i64, exponent: i32) -> f64 {
    pow10_scaled(digit as f64, exponent)
}

/// `x × 10^exponent` with a single rounding while the power of ten is exact in f64.
fn pow10_scaled(x: f64, exponent: i32) -> f64 {
    // Powers of ten up to 10^22 are exact doubles; beyond that, rounding twice is the best
    // that plain arithmetic offers and is far below a pixel.
    const EXACT: i32 = 22;
    if exponent >= 0 {
        let e = exponent.min(EXACT);
        x * 10f64.powi(e) * 10f64.powi(exponent - e)
    } else {
        let e = (-exponent).min(EXACT);
        x / 10f64.powi(e) / 10f64.powi(-exponent - e)
    }
}

/// Decimals that show a lone value without noise: enough for about six significant digits.
fn decimals_for(value: f64) -> usize {
    if value == 0.0 || !value.is_finite() {
        return 0;
    }
    let digits = 6 - value.abs().log10().floor() as i32;
    let text = format!("{value:.*}", digits.max(0) as usize);
    if text.contains('.') {
        let trimmed = text.trim_end_matches('0').trim_end_matches('.');
        trimmed.split('.').nth(1).map_or(0, str::len)
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks that ticks for `[min, max]` with `target` have exactly these labels and that
    /// each value is the double nearest its label.
    fn check_linear(min: f64, max: f64, target: usize, labels: &[&str]) {
        let ticks = linear_ticks(min, max, target);
        assert_eq!(
            ticks.labels(),
            labels,
            "[{min}, {max}] with target {target}"
        );
        for tick in &ticks.major {
            let parsed: f64 = parse_label(&tick.label);
            assert_eq!(tick.value, parsed, "value of {:?}", tick.label);
            assert!(tick.value >= min.min(max) - 1e-12 && tick.value <= max.max(min) + 1e-12);
        }
    }

    fn parse_label(label: &str) -> f64 {
        label
            .replace('−', "-")
            .parse()
            .unwrap_or_else(|_| panic!("label {label:?} is not a plain number"))
    }

    #[test]
    fn linear_ticks_on_known_ranges() {
        // The example from the brief: step 2 fits 11 units in at most 6 intervals, and
        // ticks are multiples of the step, so they start at 0, not at -1.
        check_linear(-1.3, 9.7, 6, &["0", "2", "4", "6", "8"]);
        check_linear(0.0, 1.0, 6, &["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        check_linear(
            0.0,
            1.0,
            10,
            &[
                "0.0", "0.1", "0.2", "0.3", "0.4", "0.5", "0.6", "0.7", "0.8", "0.9", "1.0",
            ],
        );
        check_linear(-2.0, 2.0, 4, &["−2", "−1", "0", "1", "2"]);
        check_linear(-1.0, 1.0, 5, &["−1.0", "−0.5", "0.0", "0.5", "1.0"]);
        check_linear(0.0, 100.0, 5, &["0", "20", "40", "60", "80", "100"]);
        check_linear(0.0, 5.0, 5, &["0", "1", "2", "3", "4", "5"]);
        check_linear(
            1.0e-3,
            1.5e-3,
            5,
            &["0.0010", "0.0011", "0.0012", "0.0013", "0.0014", "0.0015"],
        );
        check_linear(250.0, 1000.0, 6, &["400", "600", "800", "1000"]);
        // Reversed bounds describe the same range.
        check_linear(9.7, -1.3, 6, &["0", "2", "4", "6", "8"]);
    }

    #[test]
    fn a_tenth_is_printed_and_stored_without_noise() {
        let ticks = linear_ticks(0.0, 0.6, 6);
        assert_eq!(ticks.major[3].value, 0.3);
        assert_eq!(ticks.major[3].label, "0.3");
        assert_ne!(3.0 * 0.1, 0.3, "the naive product is the noisy one");
    }

    #[test]
    fn huge_and_tiny_values_use_powers_of_ten() {
        assert_eq!(
            linear_ticks(0.0, 4.0e6, 4).labels(),
            ["0", "1×10⁶", "2×10⁶", "3×10⁶", "4×10⁶"]
        );
        assert_eq!(
            linear_ticks(-5.0e-5, 5.0e-5, 5).labels(),
            ["−4×10⁻⁵", "−2×10⁻⁵", "0", "2×10⁻⁵", "4×10⁻⁵"]
        );
    }

    #[test]
    fn degenerate_linear_ranges() {
        assert_eq!(linear_ticks(3.0, 3.0, 5).labels(), ["3"]);
        assert_eq!(linear_ticks(0.1, 0.1, 5).labels(), ["0.1"]);
        assert_eq!(linear_ticks(f64::NAN, 1.0, 5), AxisTicks::default());
        assert_eq!(linear_ticks(0.0, f64::INFINITY, 5), AxisTicks::default());
    }

    #[test]
    fn nice_steps() {
        let check = |span: f64, target: usize, mantissa: i64, exponent: i32| {
            assert_eq!(
                NiceStep::for_span(span, target),
                Some(NiceStep { mantissa, exponent }),
                "span {span}, target {target}"
            );
        };
        check(11.0, 6, 2, 0);
        check(1.0, 5, 2, -1);
        check(1.0, 10, 1, -1);
        check(7.0, 1, 1, 1);
        check(1.0e-9, 4, 5, -10);
        check(3.0e12, 3, 1, 12);
        assert_eq!(NiceStep::for_span(0.0, 5), None);
    }

    #[test]
    fn plain_labels_use_the_minus_sign_and_no_negative_zero() {
        assert_eq!(format_plain(-2.0, 0), "−2");
        assert_eq!(format_plain(-0.0, 1), "0.0");
        assert_eq!(format_plain(-0.01, 1), "0.0");
        assert_eq!(format_plain(0.30000000000000004, 1), "0.3");
        assert_eq!(format_plain(12.5, 1), "12.5");
    }

    #[test]
    fn log_ticks_over_seven_decades() {
        let ticks = log10_ticks(1e-9, 1e-2, 10, LogLabelStyle::Superscript);
        assert_eq!(
            ticks.labels(),
            [
                "10⁻⁹", "10⁻⁸", "10⁻⁷", "10⁻⁶", "10⁻⁵", "10⁻⁴", "10⁻³", "10⁻²"
            ]
        );
        assert_eq!(ticks.major[3].value, 1e-6);
        assert_eq!(ticks.major[7].value, 0.01);
        // Eight minor ticks per decade between the seven gaps: 2..9 × 10⁻⁹ .. 10⁻³.
        assert_eq!(ticks.minor.len(), 7 * 8);
        assert_eq!(ticks.minor[0], 2e-9);
        assert_eq!(ticks.minor[55], 9e-3);
        assert!(ticks.minor.windows(2).all(|w| w[0] < w[1]));

        let e = log10_ticks(1e-9, 1e-2, 10, LogLabelStyle::ENotation);
        assert_eq!(e.labels()[0], "1e-9");
        assert_eq!(e.labels()[7], "1e-2");
    }

    #[test]
    fn many_decades_are_thinned_to_the_target() {
        let ticks = log10_ticks(1e-30, 1.0, 6, LogLabelStyle::Superscript);
        assert_eq!(
            ticks.labels(),
            ["10⁻³⁰", "10⁻²⁴", "10⁻¹⁸", "10⁻¹²", "10⁻⁶", "10⁰"]
        );
        // The skipped decades become the minor ticks.
        assert_eq!(ticks.minor.len(), 31 - 6);
    }

    #[test]
    fn log_ticks_that_do_not_start_on_a_decade() {
        let ticks = log10_ticks(3e-4, 2e2, 10, LogLabelStyle::Superscript);
        assert_eq!(
            ticks.labels(),
            ["10⁻³", "10⁻²", "10⁻¹", "10⁰", "10¹", "10²"]
        );
        assert_eq!(ticks.minor.first(), Some(&3e-4));
        assert_eq!(ticks.minor.last(), Some(&2e2));
    }

    #[test]
    fn narrow_log_ranges_label_one_two_five() {
        let ticks = log10_ticks(2.0, 60.0, 6, LogLabelStyle::Superscript);
        assert_eq!(ticks.labels(), ["2", "5", "10", "20", "50"]);
        let ticks = log10_ticks(3.0, 9.0, 6, LogLabelStyle::Superscript);
        assert_eq!(ticks.labels(), ["3", "4", "5", "6", "7", "8", "9"]);
        let ticks = log10_ticks(2e-7, 6e-6, 6, LogLabelStyle::Superscript);
        assert_eq!(
            ticks.labels(),
            ["2×10⁻⁷", "5×10⁻⁷", "10⁻⁶", "2×10⁻⁶", "5×10⁻⁶"]
        );
        assert_eq!(
            log10_ticks(0.0, 1.0, 5, LogLabelStyle::Superscript),
            AxisTicks::default()
        );
    }

    #[test]
    fn superscripts() {
        assert_eq!(superscript("-12"), "⁻¹²");
        assert_eq!(superscript("x+(3)"), "x⁺⁽³⁾");
        assert_eq!(format_decade(0, LogLabelStyle::Superscript), "10⁰");
    }
}
