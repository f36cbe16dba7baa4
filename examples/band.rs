//! How well does a fit know the paper model's output? The paper's
//! transmission model (`examples/specs/paper.json`) makes a record of a
//! decaying two-tone input; Gaussian noise of 2 % of the output's RMS is
//! added (seeded); five parameters (the friction's `f_c` and `k`, the
//! spring's `w`, `β`, `γ`) are fitted from a start 20 % off. The fit's
//! 95 % uncertainty band is then predicted on another input, linearized
//! (through the exact sensitivities) and by Monte Carlo (500 parameter
//! draws run as one ensemble), and compared with the noise-free truth.
//! Prints the fitted parameters, both bands' mean half-widths and how
//! often each covers the truth, and draws the band (`out/paper-band.svg`,
//! or the path given as the first argument).
//!
//! Run: `cargo run --release --example band`

use hysteron::identify::band::{Band, BandMethod};
use hysteron::identify::{fit, free_by_names, FitOptions};
use hysteron::models::Spec;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::error::Error;
use std::f64::consts::TAU;
use std::ops::Range;

/// The free parameters (unique suffixes of the paper model's names).
const FREE: [&str; 5] = ["f_c", "left.mms.k", "w", "beta", "gamma"];

/// `n` samples of two sines (`f1`, `f2` periods per record) under a
/// decaying envelope from amplitude `a`.
fn two_tone(n: usize, a: f64, f1: f64, f2: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            a * (1.0 - 0.6 * t) * ((TAU * f1 * t).sin() + 0.25 * (TAU * f2 * t).sin())
        })
        .collect()
}

/// The share of samples where `band` holds `truth`, and its mean
/// half-width.
fn coverage(band: &Band, truth: &[f64]) -> (f64, f64) {
    let inside = truth
        .iter()
        .zip(band.lower.iter().zip(&band.upper))
        .filter(|(t, (lo, hi))| *lo <= *t && *t <= *hi)
        .count();
    let half = band.half_widths();
    (
        inside as f64 / truth.len() as f64,
        half.iter().sum::<f64>() / half.len() as f64,
    )
}

fn main() -> Result<(), Box<dyn Error>> {
    let spec = Spec::from_json_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/specs/paper.json"
    ))?;
    let truth_model = spec.build()?;
    let free = free_by_names(&*truth_model, &FREE)?;

    // The record: the truth plus noise.
    let x = two_tone(3000, 1.6, 4.0, 31.0);
    let y_true = spec.build()?.run(&x)?;
    let rms = (y_true.iter().map(|v| v * v).sum::<f64>() / y_true.len() as f64).sqrt();
    let noise = Normal::new(0.0, 0.02 * rms)?;
    let mut rng = StdRng::seed_from_u64(2015);
    let y: Vec<f64> = y_true.iter().map(|v| v + noise.sample(&mut rng)).collect();

    // The fit, from 20 % off.
    let mut start = spec.build()?;
    let mut p = start.params();
    for &i in &free {
        p[i] *= 1.2;
    }
    start.set_params(&p)?;
    let fitted = fit(&*start, &x, &y, &free, &FitOptions::default())?;
    println!(
        "fit: {:?} on {} samples with noise σ = {:.4} (2 % of RMS {rms:.3})",
        fitted.report.status,
        x.len(),
        0.02 * rms
    );
    let truth = truth_model.params();
    for fp in &fitted.report.params {
        println!(
            "  {:<22} {:>9.5} ± {:<8.5} (truth {:.5})",
            fp.label(),
            fp.value,
            fp.std_error.unwrap_or(f64::NAN),
            truth[fp.index]
        );
    }

    // The band on another input, against the noise-free truth there.
    let xv = two_tone(1500, 1.3, 2.0, 17.0);
    let yv_true = spec.build()?.run(&xv)?;
    let linear = fitted.predict_band(&xv, 0.95, BandMethod::Linearized)?;
    let mc = fitted.predict_band(
        &xv,
        0.95,
        BandMethod::MonteCarlo {
            draws: 500,
            seed: 7,
        },
    )?;
    for (name, band) in [("linearized", &linear), ("monte_carlo", &mc)] {
        let (covered, half) = coverage(band, &yv_true);
        println!(
            "95 % band, {name:<11}: mean half-width {half:.5}, covers the truth at {:.1} % of {} samples{}",
            100.0 * covered,
            xv.len(),
            if band.failed_draws > 0 {
                format!(" ({} draws failed)", band.failed_draws)
            } else {
                String::new()
            }
        );
    }

    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "out/paper-band.svg".to_string());
    if let Some(dir) = std::path::Path::new(&path).parent() {
        std::fs::create_dir_all(dir)?;
    }
    draw(&path, &linear, &mc, &yv_true)?;
    println!("wrote {path}");
    Ok(())
}

/// Two panels over the sample index: the fitted output with the
/// linearized band and the truth (top); both bands' edges about the
/// fitted output, with the truth's error (bottom).
fn draw(path: &str, linear: &Band, mc: &Band, truth: &[f64]) -> Result<(), Box<dyn Error>> {
    let root = SVGBackend::new(path, (900, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let (top, bottom) = root.split_vertically(330);
    let n = truth.len() as f64;
    // (the top 30 % left free for the legend)
    let range = |v: &[&[f64]]| {
        let (lo, hi) = v
            .iter()
            .flat_map(|s| s.iter())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
                (a.min(y), b.max(y))
            });
        let span = (hi - lo).max(f64::MIN_POSITIVE);
        (lo - 0.05 * span)..(hi + 0.45 * span)
    };
    let series = |v: &[f64]| -> Vec<(f64, f64)> {
        v.iter().enumerate().map(|(k, &y)| (k as f64, y)).collect()
    };
    let blue = RGBColor(31, 119, 180);
    let purple = RGBColor(148, 103, 189);
    let orange = RGBColor(255, 127, 14);

    let mut chart = panel(
        &top,
        "Paper model, fitted on a noisy record: output on a new input with its 95 % band",
        n,
        range(&[&linear.lower, &linear.upper, truth]),
        "force F",
    )?;
    let band: Vec<(f64, f64)> = series(&linear.upper)
        .into_iter()
        .chain(series(&linear.lower).into_iter().rev())
        .collect();
    chart
        .draw_series(std::iter::once(Polygon::new(band, purple.mix(0.35))))?
        .label("95 % band (linearized)")
        .legend(move |(x, y)| {
            Rectangle::new([(x, y - 4), (x + 16, y + 4)], purple.mix(0.35).filled())
        });
    chart
        .draw_series(LineSeries::new(series(&linear.output), &blue))?
        .label("fitted model")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], blue));
    chart
        .draw_series(LineSeries::new(series(truth), orange.stroke_width(1)))?
        .label("truth (noise-free)")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], orange));
    legend(&mut chart)?;

    let about =
        |v: &[f64]| -> Vec<f64> { v.iter().zip(&linear.output).map(|(a, y)| a - y).collect() };
    let (lin_lo, lin_hi, mc_lo, mc_hi, err) = (
        about(&linear.lower),
        about(&linear.upper),
        about(&mc.lower),
        about(&mc.upper),
        about(truth),
    );
    let mut chart = panel(
        &bottom,
        "The bands' edges and the truth, about the fitted output",
        n,
        range(&[&lin_lo, &lin_hi, &mc_lo, &mc_hi, &err]),
        "F − fitted F",
    )?;
    for (k, edge) in [&lin_lo, &lin_hi].into_iter().enumerate() {
        let s = chart.draw_series(LineSeries::new(series(edge), &purple))?;
        if k == 0 {
            s.label("linearized")
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], purple));
        }
    }
    for (k, edge) in [&mc_lo, &mc_hi].into_iter().enumerate() {
        let s = chart.draw_series(LineSeries::new(series(edge), &BLACK))?;
        if k == 0 {
            s.label("Monte Carlo (500 draws)")
                .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK));
        }
    }
    chart
        .draw_series(LineSeries::new(series(&err), orange.stroke_width(1)))?
        .label("truth")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], orange));
    legend(&mut chart)?;
    root.present()?;
    Ok(())
}

/// A chart over the sample index and an output range.
type Panel<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A panel of [`draw`] on `area`: its caption, the sample index `0..n`
/// across, the output `y` (named `y_desc`) up, with its mesh drawn.
fn panel<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    n: f64,
    y: Range<f64>,
    y_desc: &str,
) -> Result<Panel<'a, 'b>, Box<dyn Error>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..n, y)?;
    chart
        .configure_mesh()
        .x_desc("sample")
        .y_desc(y_desc)
        .draw()?;
    Ok(chart)
}

/// A panel's legend, at the upper right.
fn legend<'a, 'b: 'a>(chart: &mut Panel<'a, 'b>) -> Result<(), Box<dyn Error>> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    Ok(())
}
