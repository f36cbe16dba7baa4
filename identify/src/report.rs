//! A [`FitReport`] as text.

use crate::outcome::{FitReport, FitStatus};
use std::fmt;

/// `v` with `sig` significant digits, fixed notation for moderate
/// magnitudes and scientific otherwise (like C's `%g`, trailing zeros
/// dropped). Written here because Rust's formatting has no `%g` and this
/// one function does not justify a dependency.
pub fn fmt_g(v: f64, sig: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let sig = sig.max(1);
    let exp = v.abs().log10().floor() as i32;
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (-4..sig as i32).contains(&exp) {
        let decimals = (sig as i32 - 1 - exp).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.*e}", sig - 1);
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m.to_string())),
            None => s,
        }
    }
}

/// The report as a table of the free parameters (name, start, value,
/// standard error, 95 % confidence interval), then cost, RMS, NRMSE,
/// the condition number of `JᵀJ`, one `warning:` line per
/// identifiability warning, iterations, evaluations, wall time and status (`converged (why)` or
/// `NOT CONVERGED: why`). Ends with a newline.
impl fmt::Display for FitReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = self;
        let w = r
            .params
            .iter()
            .map(|p| p.label().len())
            .max()
            .unwrap_or(0)
            .max("parameter".len());
        writeln!(
            f,
            "{:<w$}  {:>13}  {:>13}  {:>10}  95% CI",
            "parameter", "start", "value", "std error"
        )?;
        for p in &r.params {
            let se = p.std_error.map_or("-".to_string(), |s| fmt_g(s, 3));
            let ci = p.ci95.map_or("-".to_string(), |(a, b)| {
                format!("[{}, {}]", fmt_g(a, 7), fmt_g(b, 7))
            });
            writeln!(
                f,
                "{:<w$}  {:>13}  {:>13}  {:>10}  {ci}",
                p.label(),
                fmt_g(p.start, 7),
                fmt_g(p.value, 7),
                se
            )?;
        }
        writeln!(f, "cost         {:.6e}", r.cost)?;
        writeln!(f, "RMS          {:.6e}", r.rms)?;
        match r.nrmse {
            Some(v) => writeln!(f, "NRMSE        {v:.6e}")?,
            None => writeln!(f, "NRMSE        - (output zero throughout)")?,
        }
        if r.records.len() > 1 {
            writeln!(f, "record  samples  RMS           NRMSE")?;
            for (i, rf) in r.records.iter().enumerate() {
                let nrmse = rf.nrmse.map_or("-".to_string(), |v| format!("{v:.6e}"));
                writeln!(f, "{i:>6}  {:>7}  {:.6e}  {nrmse}", rf.samples, rf.rms)?;
            }
        }
        match r.condition_number {
            Some(k) => writeln!(f, "cond(JᵀJ)    {k:.3e}")?,
            None => writeln!(f, "cond(JᵀJ)    - (singular)")?,
        }
        if let Some(st) = &r.starts {
            writeln!(
                f,
                "starts       {} ({} reached the best cost within 1 % or rounding; the best was start {})",
                st.costs.len(),
                st.reached,
                st.best
            )?;
        }
        for w in &r.warnings {
            writeln!(f, "warning: {w}")?;
        }
        writeln!(f, "iterations   {}", r.iterations)?;
        writeln!(f, "evaluations  {}", r.evaluations)?;
        let jacobian = match r.jacobian {
            crate::options::Jacobian::Exact => "exact (forward-mode derivatives)",
            crate::options::Jacobian::FiniteDifferences => "central finite differences",
        };
        writeln!(f, "jacobian     {jacobian}")?;
        writeln!(f, "wall time    {:.3} s", r.wall_time.as_secs_f64())?;
        match &r.status {
            FitStatus::Converged(why) => writeln!(f, "status       converged ({why})"),
            FitStatus::NotConverged(why) | FitStatus::Failed(why) => {
                writeln!(f, "status       NOT CONVERGED: {why}")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fmt_g_is_short_and_exact_enough() {
        assert_eq!(fmt_g(1.5, 7), "1.5");
        assert_eq!(fmt_g(0.0, 7), "0");
        assert_eq!(fmt_g(-2.0, 7), "-2");
        assert_eq!(fmt_g(1.0 / 3.0, 7), "0.3333333");
        assert_eq!(fmt_g(12345.678, 7), "12345.68");
        assert_eq!(fmt_g(1.23456789e-7, 4), "1.235e-7");
        assert_eq!(fmt_g(2.5e9, 7), "2.5e9");
        assert_eq!(fmt_g(f64::NAN, 7), "NaN");
    }
}
