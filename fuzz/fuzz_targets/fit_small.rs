//! `fit_small`: `hysteron_identify::fit` on a registered leaf with a
//! perturbed parameter vector, a small record (≤ 64 samples, the output
//! either arbitrary or the model's own with other parameters) and a small
//! evaluation budget. Errors are fine; panics and hangs are not. A fit
//! that returns reports finite numbers, a model at the reported
//! parameters inside their domains, a cost that is not NaN (an overflow
//! to +∞ is allowed) and that matches a rerun.
#![no_main]

use arbitrary::Arbitrary;
use hysteron::identify::{fit, FitOptions};
use hysteron::operators::Operator;
use hysteron_fuzz::{bits, samples, LeafChoice, Param, Sample};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    model: LeafChoice,
    /// The record's output: the model's at these parameters, or `ys`.
    truth: Option<Vec<Param>>,
    xs: Vec<Sample>,
    ys: Vec<Sample>,
    /// Which parameters are free (bit `i` for parameter `i`).
    free: u32,
    patience: u8,
    stride: u8,
    tol: u8,
}

fuzz_target!(|input: Input| {
    let Some(model) = input.model.build() else {
        return;
    };
    let stride = 1 + usize::from(input.stride % 3);
    // the record's lengths agree (x.len() = stride · y.len()), mostly
    let n = input.xs.len().min(64) / stride * stride;
    let xs = samples(&input.xs[..n]);
    let ys: Vec<f64> = match &input.truth {
        Some(truth) => {
            let Some(mut m) = (hysteron_fuzz::LeafChoice {
                index: input.model.index,
                params: truth.clone(),
            })
            .build() else {
                return;
            };
            let Ok(y) = m.run(&xs) else {
                return;
            };
            y.into_iter().step_by(stride).collect()
        }
        None => {
            let mut ys = samples(&input.ys[..input.ys.len().min(n / stride)]);
            ys.resize(n / stride, 0.0);
            ys
        }
    };
    let k = model.n_params().min(32);
    let free: Vec<usize> = (0..k).filter(|i| input.free >> i & 1 == 1).collect();
    let tol = [1e-12, 1e-6, 1e-2, 0.0][usize::from(input.tol % 4)];
    let opts = FitOptions {
        ftol: tol,
        xtol: tol,
        gtol: 0.0,
        patience: 1 + usize::from(input.patience % 3),
        parallel: false,
        stride,
        ..FitOptions::default()
    };
    let Ok(f) = fit(&*model, &xs, &ys, &free, &opts) else {
        return;
    };
    let r = &f.report;
    // `½ Σ r²` of finite residuals may overflow to +∞ (a record near 1e200):
    // honest, unlike a NaN
    assert!(r.cost >= 0.0, "cost {}", r.cost);
    assert!(r.rms >= 0.0, "rms {}", r.rms);
    assert_eq!(bits(&f.model.params()), bits(&r.all_params));
    let domains = f.model.param_domains();
    for ((v, d), name) in r.all_params.iter().zip(&domains).zip(f.model.param_names()) {
        assert!(d.contains(*v), "fitted {name} = {v} outside {d:?}");
    }
    for p in &r.params {
        assert!(p.value.is_finite() && p.start.is_finite(), "{p:?}");
        assert_eq!(p.value.to_bits(), r.all_params[p.index].to_bits());
    }
    // the reported cost is the fitted model's
    let mut m = f.model.clone();
    if let Ok(out) = m.run(&xs) {
        let cost: f64 = 0.5
            * out
                .iter()
                .step_by(stride)
                .zip(&ys)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>();
        assert!(
            (cost - r.cost).abs() <= 1e-9 * cost.abs().max(1e-300) || cost == r.cost,
            "reported cost {} but the fitted model's is {cost}",
            r.cost
        );
    }
});
