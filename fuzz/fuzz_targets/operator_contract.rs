//! `operator_contract`: a random model — every registered leaf (`LEAVES`)
//! with a perturbed parameter vector, and combinators of them (cascade,
//! parallel, scaled, feedback, series with limits, inverse, oversample) —
//! run on a random input. `set_params` must validate (a rejected vector
//! changes nothing, an accepted one lies in the declared domains); then
//! `check_contract`: finite outputs or a typed error, `process` equal bit
//! for bit to the trial + commit loop on a clone, same state after both,
//! replay after reset identical.
#![no_main]

use arbitrary::Arbitrary;
use hysteron_fuzz::{check_contract, samples, Sample, Tree};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    model: Tree,
    xs: Vec<Sample>,
}

fuzz_target!(|input: Input| {
    // two levels of combinators: nested implicit solvers multiply their cost
    let Some(op) = input.model.build(2) else {
        return;
    };
    let xs = samples(&input.xs[..input.xs.len().min(96)]);
    check_contract(op.name(), &op, &xs);
});
