//! A tour of the algebra: builds a few models from operators and
//! combinators, drives them with a decaying sine and prints what each does.
//!
//! Run: `cargo run --release --example tour`

use hysteron::models::energy::closed_loop_work;
use hysteron::prelude::*;
use std::time::Instant;

fn report(name: &str, model: &mut dyn Operator<f64>, x: &[f64], period: usize) -> Result<()> {
    model.reset();
    let t0 = Instant::now();
    let y = model.run(x)?;
    let dt = t0.elapsed().as_secs_f64();
    let peak = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let first = closed_loop_work(&x[..=period], &y[..=period]).abs();
    println!(
        "{name:<44} params {:>2}  peak |y| {peak:>8.4}  first-cycle loop area {first:>8.4}  {:>7.1} ns/sample",
        model.n_params(),
        dt * 1e9 / x.len() as f64,
    );
    Ok(())
}

fn main() -> Result<()> {
    let period = 2000;
    let x: Vec<f64> = (0..20 * period)
        .map(|i| {
            let t = i as f64 / period as f64;
            1.5 * (-0.1 * t).exp() * (std::f64::consts::TAU * t).sin()
        })
        .collect();

    let spring = BoucWen::from_params(BoucWenParams {
        w: 0.4,
        alpha: 1.0,
        beta: 3.0,
        gamma: 1.0,
        n: 1.0,
        h0: 0.0,
        z0: 0.0,
        stiffness: StiffnessMap::new(vec![0.0, 0.6, 1.2], vec![8.0, 10.0, 16.0])?,
    })?;
    let r: Vec<f64> = (0..16).map(|j| 0.1 * j as f64).collect();
    let w: Vec<f64> = r.iter().map(|r| (-2.0 * r).exp() / 4.0).collect();

    let mut models: Vec<(&str, Box<dyn Operator<f64>>)> = vec![
        ("play r=0.2", Play::new(0.2)?.boxed()),
        (
            "Prandtl-Ishlinskii, 16 plays",
            PiBank::new(0.2, r, w)?.boxed(),
        ),
        ("MMS friction Fc=2 K=20", Mms::new(2.0, 20.0)?.boxed()),
        (
            "Bouc-Wen spring, 3-knot stiffness map",
            spring.clone().boxed(),
        ),
        (
            "MMS in series with spring, gap b=0.3",
            Mms::new(2.0, 40.0)?
                .series(spring.clone())
                .with_limits(TravelLimits::Gap { b: 0.3, r0: 0.0 })?
                .boxed(),
        ),
        (
            "spring with play in the feedback path",
            spring.feedback(Play::new(0.05)?.scaled(0.02)?).boxed(),
        ),
    ];
    println!("input: decaying sine, amplitude 1.5, {} samples", x.len());
    for (name, model) in models.iter_mut() {
        report(name, model.as_mut(), &x, period)?;
    }
    Ok(())
}
