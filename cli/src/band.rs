//! The options of an uncertainty band, shared by `fit` (`--band`) and
//! `validate` (`--covariance`), and the covariance file that carries a
//! fit's parameter covariance from one to the other
//! ([`Covariance`], JSON).

use crate::csvio::{self, CsvIoError};
use crate::identify::band::{self, Band, BandError, BandMethod, Covariance};
use crate::Operator;
use std::path::{Path, PathBuf};

/// `--band-level`, `--band-method`, `--band-draws`, `--band-seed`.
#[derive(Debug, Clone, PartialEq, clap::Args)]
pub struct BandArgs {
    /// The band's probability content, in (0, 1).
    #[arg(long, value_name = "P", default_value_t = 0.95, value_parser = level, allow_hyphen_values = true)]
    pub band_level: f64,
    /// How the parameters' covariance is carried to the output:
    /// `linearized` (first order, exact sensitivities) or `monte_carlo`
    /// (--band-draws parameter vectors drawn and simulated, empirical
    /// quantiles per sample).
    #[arg(long, value_enum, value_name = "METHOD", default_value_t = MethodArg::Linearized)]
    pub band_method: MethodArg,
    /// Monte-Carlo draws (at least 1; the level needs at least
    /// 2/(1 − level) of them to run, 40 at 0.95).
    #[arg(long, value_name = "N", default_value_t = 1000, value_parser = crate::args::at_least_1, allow_negative_numbers = true)]
    pub band_draws: usize,
    /// Seed of the Monte-Carlo draws (the same seed, the same band).
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub band_seed: u64,
}

impl Default for BandArgs {
    /// The flags' defaults: 0.95, linearized, 1000 draws, seed 0.
    fn default() -> Self {
        BandArgs {
            band_level: 0.95,
            band_method: MethodArg::Linearized,
            band_draws: 1000,
            band_seed: 0,
        }
    }
}

impl BandArgs {
    /// The method with its draws and seed.
    pub fn method(&self) -> BandMethod {
        match self.band_method {
            MethodArg::Linearized => BandMethod::Linearized,
            MethodArg::MonteCarlo => BandMethod::MonteCarlo {
                draws: self.band_draws,
                seed: self.band_seed,
            },
        }
    }

    /// The band of `model` along `x` with the covariance `cov`.
    ///
    /// # Errors
    /// The library's [`BandError`].
    pub fn band(
        &self,
        model: &(dyn Operator<f64> + 'static),
        cov: &Covariance,
        x: &[f64],
    ) -> Result<Band, BandError> {
        band::predict_band(model, cov, x, self.band_level, self.method())
    }
}

/// `--band-method`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodArg {
    /// First order in the parameters.
    Linearized,
    /// Drawn parameter vectors.
    #[value(name = "monte_carlo")]
    MonteCarlo,
}

/// `--band-level`: a number in the open interval (0, 1).
pub fn level(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{}` is not a number", s.trim()))?;
    if v > 0.0 && v < 1.0 {
        Ok(v)
    } else {
        Err(format!(
            "must lie in (0, 1), such as 0.95 (got {})",
            s.trim()
        ))
    }
}

/// Why a covariance file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum CovarianceFileError {
    /// The file could not be read.
    #[error("--covariance `{}`: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not a covariance (JSON with names, indices, values,
    /// matrix).
    #[error("--covariance `{}`: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// Where and why.
        message: String,
    },
    /// The file's parameters are not those of the model, or not at the
    /// model's values (the covariance of another fit).
    #[error("--covariance `{}`: {message}", path.display())]
    Mismatch {
        /// The file.
        path: PathBuf,
        /// Which parameter and how.
        message: String,
    },
}

/// The covariance as written by `fit --covariance`: pretty JSON.
pub fn to_json(cov: &Covariance) -> Result<String, serde_json::Error> {
    serde_json::to_string_pretty(cov).map(|s| s + "\n")
}

/// Reads a covariance file and checks it against `model`: every name one
/// of the model's parameters, its index resolved there, and its value the
/// model's (the file belongs to the fit that gave the model's spec).
pub fn read_for(
    path: &Path,
    model: &(dyn Operator<f64> + 'static),
) -> Result<Covariance, CovarianceFileError> {
    let text = std::fs::read_to_string(path).map_err(|source| CovarianceFileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut cov: Covariance =
        serde_json::from_str(&text).map_err(|e| CovarianceFileError::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    let mismatch = |message: String| CovarianceFileError::Mismatch {
        path: path.to_path_buf(),
        message,
    };
    if cov.values.len() != cov.names.len() {
        return Err(mismatch(format!(
            "{} names but {} values",
            cov.names.len(),
            cov.values.len()
        )));
    }
    let names = model.param_names();
    let params = model.params();
    let mut indices = Vec::with_capacity(cov.names.len());
    for (name, &value) in cov.names.iter().zip(&cov.values) {
        let Some(i) = names.iter().position(|n| n == name) else {
            return Err(mismatch(format!(
                "the model has no parameter `{name}` (it has {})",
                names.join(", ")
            )));
        };
        let own = params.get(i).copied().unwrap_or(f64::NAN);
        if (own - value).abs() > 1e-12 * value.abs().max(f64::MIN_POSITIVE) {
            return Err(mismatch(format!(
                "parameter `{name}` is {} in the model but {} in the covariance: give the \
                 fitted spec of the fit that wrote it",
                csvio::fmt_f64(own),
                csvio::fmt_f64(value)
            )));
        }
        indices.push(i);
    }
    cov.indices = indices;
    Ok(cov)
}

/// A band's rows as CSV: `record` (with several records), the input
/// column, `output`, `lower`, `upper`.
pub fn write_csv(path: &Path, input: &str, bands: &[(Vec<f64>, Band)]) -> Result<(), CsvIoError> {
    let several = bands.len() > 1;
    let wrap = |e: csv::Error| csvio::csv_write_error(path, e);
    csvio::write_csv_atomic_with(
        path,
        |e| e,
        |out| {
            let mut header: Vec<&str> = if several { vec!["record"] } else { vec![] };
            header.extend([input, "output", "lower", "upper"]);
            out.write_record(&header).map_err(wrap)?;
            let mut row: Vec<String> = Vec::with_capacity(5);
            for (r, (x, b)) in bands.iter().enumerate() {
                for (k, &xk) in x.iter().enumerate() {
                    row.clear();
                    if several {
                        row.push(r.to_string());
                    }
                    row.extend(
                        [
                            Some(xk),
                            b.output.get(k).copied(),
                            b.lower.get(k).copied(),
                            b.upper.get(k).copied(),
                        ]
                        .map(|v| csvio::fmt_f64(v.unwrap_or(f64::NAN))),
                    );
                    out.write_record(&row).map_err(wrap)?;
                }
            }
            Ok(())
        },
    )
}
