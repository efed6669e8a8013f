//! Numbers written for people: a measured value to a few significant digits.

/// A float to `digits` (≥ 1) significant digits: plain between 1e-3 and 1e6 (trailing zeros
/// dropped; integer digits kept), scientific otherwise; `0` for either zero, `NaN`, `inf` and `-inf` as such.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 {
        return "0".to_string(); // -0.0 too: a zero energy is not negative
    }
    let digits = digits.max(1) as i32;
    if !x.is_finite() || (1e-3..1e6).contains(&x.abs()) {
        let decimals = if !x.is_finite() { 1 } else { (digits - 1 - x.abs().log10().floor() as i32).max(0) as usize };
        let text = format!("{x:.decimals$}");
        if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').to_string() } else { text }
    } else {
        format!("{x:.*e}", (digits - 1) as usize)
    }
}

/// A value a user gave, in a message, exactly (the shortest text that reads back to it): plain
/// unless very large or very small, where it is scientific (`1e-300`, not 300 digits).
pub fn exact(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-6..1e16).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

/// A measured value in a message: 4 significant digits.
pub fn short(x: f64) -> String {
    significant(x, 4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_cases_stay_short_and_say_what_they_are() {
        assert_eq!(short(f64::NAN), "NaN");
        assert_eq!(short(f64::INFINITY), "inf");
        assert_eq!(short(f64::NEG_INFINITY), "-inf");
        assert_eq!(short(1e177), "1.000e177");
        assert_eq!(short(-2.5e177), "-2.500e177");
        assert_eq!(short(1e-300), "1.000e-300");
        assert_eq!(short(-0.0), "0");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(f64::MAX).len(), 9);
        assert_eq!(short(f64::MIN_POSITIVE), "2.225e-308");
        assert_eq!(short(5e-324), "4.941e-324", "a subnormal is scientific too");
    }

    #[test]
    fn given_values_read_back_exactly_and_stay_short() {
        for (x, text) in [(-0.00001, "-0.00001"), (0.0, "0"), (0.7, "0.7"), (1e-300, "1e-300"), (1e200, "1e200")] {
            assert_eq!(exact(x), text);
        }
        assert_eq!((exact(f64::NAN), exact(f64::NEG_INFINITY)), ("NaN".to_string(), "-inf".to_string()));
        for x in [0.1 + 0.2, f64::MAX, f64::MIN_POSITIVE, 5e-324, -123_456.789, 1e15 + 0.5] {
            assert_eq!(exact(x).parse::<f64>(), Ok(x), "{}", exact(x));
            assert!(exact(x).len() <= 24, "{}", exact(x));
        }
    }

    #[test]
    fn ordinary_values_are_plain_with_four_digits() {
        assert_eq!(short(0.123456), "0.1235");
        assert_eq!(short(1234.56), "1235");
        assert_eq!(short(123_456.7), "123457", "a plain number keeps its integer digits");
        assert_eq!(short(0.5), "0.5", "trailing zeros dropped");
        assert_eq!(short(-2.71828e-2), "-0.02718");
        assert_eq!(short(2e6), "2.000e6");
        assert_eq!(short(0.000_999), "9.990e-4");
        assert_eq!(significant(1.5, 0), "2", "at least one digit");
    }
}
