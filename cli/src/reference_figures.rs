//! `hysteron operators --figures DIR`: besides the registry's listing,
//! one small loop figure per operator and combinator for the guide's
//! reference pages (`docs/reference/figures/KIND.svg`).

use crate::csvio;
use crate::models::spec::registry::LEAVES;
use crate::models::spec::COMBINATOR_LAWS;
use crate::models::Spec;
use crate::output::OutputError;
use crate::plot;
use std::path::{Path, PathBuf};

/// Samples of the figures' input.
const SAMPLES: usize = 400;

/// The input every figure is drawn over: three periods of a sine whose
/// amplitude falls linearly from 2 to 0.4, so that a rate-independent
/// operator draws its outer loop and loops nested inside it.
pub fn figure_input() -> Vec<f64> {
    (0..SAMPLES)
        .map(|i| {
            let t = i as f64 / SAMPLES as f64;
            (2.0 - 1.6 * t) * (std::f64::consts::TAU * 3.0 * t).sin()
        })
        .collect()
}

/// The example spec of every registered leaf and every combinator, each
/// with its spec `type`.
pub fn examples() -> Result<Vec<(&'static str, Spec)>, String> {
    let mut out: Vec<(&'static str, Spec)> = LEAVES
        .iter()
        .map(|l| (l.kind(), l.example_spec()))
        .collect();
    for c in COMBINATOR_LAWS {
        let spec = Spec::from_json(c.example).map_err(|e| format!("{}: {e}", c.kind))?;
        out.push((c.kind, spec));
    }
    Ok(out)
}

/// The loop figure of `spec` over [`figure_input`], as an SVG document.
pub fn loop_figure(kind: &str, spec: &Spec) -> Result<String, String> {
    let x = figure_input();
    let mut model = spec.build().map_err(|e| format!("{kind}: {e}"))?;
    let y = model.run(&x).map_err(|e| format!("{kind}: {e}"))?;
    let panel = plot::loop_panel(&format!("{kind}: the example spec"), "x", "y", &x, &y);
    plot::render(&[panel], 1, 1, (480, 360)).map_err(|e| format!("{kind}: {e}"))
}

/// Writes `DIR/KIND.svg` for every operator and combinator (creating
/// `DIR`); returns the files written.
pub fn write_figures(dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| OutputError::PlotDir(dir.to_path_buf(), e).to_string())?;
    let mut written = Vec::new();
    for (kind, spec) in examples()? {
        let path = dir.join(format!("{kind}.svg"));
        let svg = loop_figure(kind, &spec)?;
        csvio::write_string_atomic(&path, &svg).map_err(|e| OutputError::Write(e).to_string())?;
        written.push(path);
    }
    Ok(written)
}
