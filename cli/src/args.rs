//! Parsers of the program's numeric options, for clap's `value_parser`:
//! each gives a one-line [`ArgError`] saying what the option needs
//! (`must be positive and finite`, `must be at least 1`), which clap shows
//! as `invalid value '-1' for '--dt <SECONDS>': must be positive and
//! finite`. Negative numbers reach them (the options are declared with
//! `allow_negative_numbers` or `allow_hyphen_values`), so `--dt -1` is
//! refused for its value, not read as an unknown option.

/// Why an option's value was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ArgError {
    /// Not a number at all.
    #[error("`{0}` is not a number")]
    NotANumber(String),
    /// Not a whole number.
    #[error("`{0}` is not a whole number")]
    NotAnInteger(String),
    /// A number that must be positive and finite is not.
    #[error("must be positive and finite (got {0})")]
    NotPositive(String),
    /// A number that must be non-negative and finite is not.
    #[error("must be finite and ≥ 0 (got {0})")]
    Negative(String),
    /// A whole number below its least value.
    #[error("must be at least {min} (got {value})")]
    TooSmall {
        /// The least accepted value.
        min: usize,
        /// The value given.
        value: String,
    },
    /// A whole number above its greatest value.
    #[error("must be at most {max} (got {value})")]
    TooLarge {
        /// The greatest accepted value.
        max: usize,
        /// The value given.
        value: String,
    },
}

fn float(s: &str) -> Result<f64, ArgError> {
    s.trim()
        .parse()
        .map_err(|_| ArgError::NotANumber(s.to_string()))
}

/// A number `> 0` and finite (a sample period).
pub fn positive_f64(s: &str) -> Result<f64, ArgError> {
    let v = float(s)?;
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(ArgError::NotPositive(s.trim().to_string()))
    }
}

/// A number `≥ 0` and finite (a tolerance).
pub fn non_negative_f64(s: &str) -> Result<f64, ArgError> {
    let v = float(s)?;
    if v >= 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(ArgError::Negative(s.trim().to_string()))
    }
}

/// A whole number in `min..=max` (a count).
pub fn integer_in(s: &str, min: usize, max: usize) -> Result<usize, ArgError> {
    let t = s.trim();
    let v: i128 = t.parse().map_err(|_| {
        if float(t).is_ok() {
            ArgError::NotAnInteger(t.to_string())
        } else {
            ArgError::NotANumber(t.to_string())
        }
    })?;
    // Every usize is an i128.
    if v < min as i128 {
        Err(ArgError::TooSmall {
            min,
            value: t.to_string(),
        })
    } else if v > max as i128 {
        Err(ArgError::TooLarge {
            max,
            value: t.to_string(),
        })
    } else {
        Ok(v as usize)
    }
}

/// A whole number `≥ 1` (`--patience`).
pub fn at_least_1(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 1, usize::MAX)
}

/// `--samples-per-period` of `analyze`: at least 8 (that it is a multiple
/// of 4 is checked with the other sine options).
pub fn samples_per_period(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 8, usize::MAX)
}

/// `--settle-periods` of `analyze`: at least 2.
pub fn settle_periods(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 2, usize::MAX)
}

/// `--points` of `identify-paper`: 2 to 999.
pub fn points(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 2, 999)
}

/// `--precision` of `analyze`: 1 to 17 significant digits.
pub fn precision(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 1, 17)
}

/// `--samples` of `bench`: 1 to 10⁹.
pub fn bench_samples(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 1, 1_000_000_000)
}

/// `--runs` of `bench`: 1 to 1000.
pub fn bench_runs(s: &str) -> Result<usize, ArgError> {
    integer_in(s, 1, 1000)
}

/// `--samples` of `sobol`: 16 to 65536 (that it is a power of two is
/// checked with the other options).
pub fn sobol_samples(s: &str) -> Result<usize, ArgError> {
    integer_in(
        s,
        hysteron::identify::sobol::MIN_SAMPLES,
        hysteron::identify::sobol::MAX_SAMPLES,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_say_what_is_needed() {
        assert_eq!(positive_f64("0.5"), Ok(0.5));
        for bad in ["-1", "0", "inf", "-0", "NaN"] {
            let e = positive_f64(bad).unwrap_err().to_string();
            assert!(e.starts_with("must be positive and finite"), "{e}");
        }
        assert_eq!(non_negative_f64("0"), Ok(0.0));
        assert!(non_negative_f64("-1e-9").is_err());
        assert_eq!(at_least_1("3"), Ok(3));
        let message = |r: Result<usize, ArgError>| r.unwrap_err().to_string();
        for (got, expected) in [
            (message(at_least_1("0")), "must be at least 1 (got 0)"),
            (message(at_least_1("-5")), "must be at least 1 (got -5)"),
            (message(at_least_1("2.5")), "`2.5` is not a whole number"),
            (message(points("1000")), "must be at most 999 (got 1000)"),
            (
                message(at_least_1("99999999999999999999999")),
                "must be at most 18446744073709551615 (got 99999999999999999999999)",
            ),
        ] {
            assert_eq!(got, expected);
        }
        assert_eq!(
            positive_f64("abc").unwrap_err().to_string(),
            "`abc` is not a number"
        );
    }
}
