//! What the fuzz targets share: decoding input samples and parameter
//! values from fuzzer data, building registered leaves and combinators of
//! them, and the trial/commit contract checked on any boxed operator.

use arbitrary::Arbitrary;
use hysteron::composition::TravelLimits;
use hysteron::models::spec::registry::LEAVES;
use hysteron::operators::{Error, Operator};
use hysteron::prelude::{OperatorExt, Oversample};

/// A boxed `f64` operator, as specs build them.
pub type Op = Box<dyn Operator<f64>>;

/// One input sample: mostly moderate values on a fine grid (where the
/// operators' interesting behaviour is), sometimes any `f64` at all.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Sample {
    /// `k / 256`: steps of about 0.004 up to ±128.
    Grid(i16),
    /// `k / 2^20`: tiny steps around zero.
    Fine(i16),
    /// The same as the previous sample (a standstill).
    Repeat,
    /// Any bit pattern: huge, subnormal, infinite, NaN.
    Raw(f64),
}

/// The samples as values (`Repeat` at the start means `0`).
pub fn samples(s: &[Sample]) -> Vec<f64> {
    let mut prev = 0.0;
    s.iter()
        .map(|s| {
            prev = match *s {
                Sample::Grid(k) => f64::from(k) / 256.0,
                Sample::Fine(k) => f64::from(k) / 1_048_576.0,
                Sample::Repeat => prev,
                Sample::Raw(v) => v,
            };
            prev
        })
        .collect()
}

/// Decodes samples from raw bytes (for targets that are not
/// structure-aware): two bytes each, as `i16 / 256`, with the byte pair
/// `7f 7f` introducing a raw little-endian `f64` in the next eight bytes.
pub fn samples_from_bytes(mut bytes: &[u8], max: usize) -> Vec<f64> {
    let mut xs = Vec::new();
    while xs.len() < max && bytes.len() >= 2 {
        if bytes[0] == 0x7f && bytes[1] == 0x7f && bytes.len() >= 10 {
            let raw: [u8; 8] = bytes[2..10].try_into().unwrap_or([0; 8]);
            xs.push(f64::from_le_bytes(raw));
            bytes = &bytes[10..];
        } else {
            xs.push(f64::from(i16::from_le_bytes([bytes[0], bytes[1]])) / 256.0);
            bytes = &bytes[2..];
        }
    }
    xs
}

/// One entry of a parameter vector, relative to a valid example value.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Param {
    /// The example's value.
    Keep,
    /// The example's value times `1 + k/64` (a factor in `[-1, 3)`).
    Scale(i8),
    /// The example's value plus `k / 64`.
    Shift(i8),
    /// Any bit pattern (most are rejected by validation: that is checked).
    Raw(f64),
}

impl Param {
    /// The value replacing `example`.
    pub fn apply(self, example: f64) -> f64 {
        match self {
            Param::Keep => example,
            Param::Scale(k) => example * (1.0 + f64::from(k) / 64.0),
            Param::Shift(k) => example + f64::from(k) / 64.0,
            Param::Raw(v) => v,
        }
    }
}

/// A registered leaf (by index into `LEAVES`, modulo its length) with its
/// example's parameter vector perturbed by `params` (missing entries kept).
#[derive(Arbitrary, Debug, Clone)]
pub struct LeafChoice {
    /// Index into `LEAVES` (taken modulo its length).
    pub index: u8,
    /// Perturbations of the example's flat parameters, in order.
    pub params: Vec<Param>,
}

impl LeafChoice {
    /// The leaf built from its example, then given the perturbed vector
    /// through `set_params` (which must validate it: `Err` is fine).
    pub fn build(&self) -> Option<Op> {
        let leaf = LEAVES[usize::from(self.index) % LEAVES.len()];
        let mut op = match leaf.build(&leaf.example()) {
            Ok(op) => op,
            Err(e) => panic!("{}: the example does not build: {e}", leaf.kind()),
        };
        let example = op.params();
        let p: Vec<f64> = example
            .iter()
            .enumerate()
            .map(|(i, &v)| self.params.get(i).map_or(v, |q| q.apply(v)))
            .collect();
        match op.set_params(&p) {
            Ok(()) => {
                let domains = op.param_domains();
                for ((v, d), name) in op.params().iter().zip(&domains).zip(op.param_names()) {
                    assert!(
                        d.contains(*v),
                        "{}: set_params accepted {name} = {v} outside {d:?}",
                        leaf.kind()
                    );
                }
                Some(op)
            }
            Err(_) => {
                // a rejected vector changes nothing
                assert_eq!(
                    bits(&op.params()),
                    bits(&example),
                    "{}: a rejected set_params changed the parameters",
                    leaf.kind()
                );
                None
            }
        }
    }
}

/// A model: a leaf or a combinator of models.
#[derive(Arbitrary, Debug, Clone)]
pub enum Tree {
    /// A registered leaf.
    Leaf(LeafChoice),
    /// `second[first[x]]`.
    Cascade(Box<Tree>, Box<Tree>),
    /// `left[x] + right[x]`.
    Parallel(Box<Tree>, Box<Tree>),
    /// `w · inner[x]` with `w = k / 16`.
    Scaled(i8, Box<Tree>),
    /// `forward[x − back[y]]`.
    Feedback(Box<Tree>, Box<Tree>),
    /// Mechanical series with optional travel limits (`k / 64`).
    Series(Box<Tree>, Box<Tree>, Limits),
    /// Numerical inverse.
    Inverse(Box<Tree>),
    /// `q = 1 + k % 8` sub-steps per sample.
    Oversample(u8, Box<Tree>),
}

/// Travel limits of a series, in steps of 1/64.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Limits {
    /// No limits.
    None,
    /// `[lo, hi]`.
    Range(i8, i8),
    /// A gap of width `b` starting at `r0`.
    Gap(i8, i8),
}

impl Tree {
    /// Builds the model; combinators deeper than `depth` levels are cut to
    /// their first leaf (nested implicit solvers multiply their cost).
    /// `None` where a part is rejected (an error: fine).
    pub fn build(&self, depth: usize) -> Option<Op> {
        let sub = |t: &Tree| t.build(depth.saturating_sub(1));
        if depth == 0 {
            return self.first_leaf().build();
        }
        Some(match self {
            Tree::Leaf(l) => l.build()?,
            Tree::Cascade(a, b) => sub(a)?.then(sub(b)?).boxed(),
            Tree::Parallel(a, b) => sub(a)?.plus(sub(b)?).boxed(),
            Tree::Scaled(k, a) => sub(a)?.scaled(f64::from(*k) / 16.0).ok()?.boxed(),
            Tree::Feedback(a, b) => sub(a)?.feedback(sub(b)?).boxed(),
            Tree::Series(a, b, limits) => {
                let s = |k: i8| f64::from(k) / 64.0;
                let limits = match *limits {
                    Limits::None => TravelLimits::None,
                    Limits::Range(lo, hi) => TravelLimits::Range {
                        lo: s(lo),
                        hi: s(hi),
                    },
                    Limits::Gap(b, r0) => TravelLimits::Gap { b: s(b), r0: s(r0) },
                };
                sub(a)?.series(sub(b)?).with_limits(limits).ok()?.boxed()
            }
            Tree::Inverse(a) => sub(a)?.inverse().boxed(),
            Tree::Oversample(q, a) => Oversample::new(sub(a)?, 1 + usize::from(*q % 8))
                .ok()?
                .boxed(),
        })
    }

    fn first_leaf(&self) -> &LeafChoice {
        match self {
            Tree::Leaf(l) => l,
            Tree::Cascade(a, _)
            | Tree::Parallel(a, _)
            | Tree::Scaled(_, a)
            | Tree::Feedback(a, _)
            | Tree::Series(a, _, _)
            | Tree::Inverse(a)
            | Tree::Oversample(_, a) => a.first_leaf(),
        }
    }
}

/// The bit patterns (the contract's notion of equality: bit for bit).
pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|y| y.to_bits()).collect()
}

/// The index an error of `process` names (`AtSample`), if any.
fn error_index(e: &Error) -> Option<usize> {
    match e {
        Error::AtSample { index, .. } => Some(*index),
        _ => None,
    }
}

/// What a trial + commit loop gives: the outputs up to the first failing
/// sample, and that sample's index.
fn trial_commit_loop(op: &mut Op, xs: &[f64], label: &str) -> (Vec<f64>, Option<usize>) {
    let mut out = Vec::with_capacity(xs.len());
    for (i, &x) in xs.iter().enumerate() {
        match op.trial(x) {
            Ok(t) => {
                assert!(
                    t.output.is_finite(),
                    "{label}: trial({x}) at sample {i} gave output {} without an error",
                    t.output
                );
                assert!(
                    !t.tangent.is_nan(),
                    "{label}: trial({x}) at sample {i} gave a NaN tangent"
                );
                assert!(x.is_finite(), "{label}: non-finite input {x} accepted");
                op.commit();
                out.push(t.output);
            }
            Err(_) => return (out, Some(i)),
        }
    }
    (out, None)
}

/// A trial's outcome as bits, for comparing two operators' states.
fn probe(op: &mut Op, x: f64) -> Option<(u64, u64)> {
    op.trial(x)
        .ok()
        .map(|t| (t.output.to_bits(), t.tangent.to_bits()))
}

/// The contract on `op` and input `xs`:
/// * every output is finite or the call is an error (no silent NaN, no
///   accepted non-finite input);
/// * `process` equals the trial + commit loop on a clone bit for bit, and
///   fails (an [`Error::AtSample`]) exactly where the loop fails;
/// * both leave the same state (trials after them agree bit for bit);
/// * a replay after `reset` is identical.
pub fn check_contract(label: &str, op: &Op, xs: &[f64]) {
    let mut a = op.clone();
    let mut ys = vec![0.0; xs.len()];
    let processed = a.process(xs, &mut ys);
    let mut b = op.clone();
    let (looped, failed) = trial_commit_loop(&mut b, xs, label);
    match (&processed, failed) {
        (Ok(()), None) => {
            assert_eq!(bits(&ys), bits(&looped), "{label}: process vs trial/commit");
            for (i, y) in ys.iter().enumerate() {
                assert!(y.is_finite(), "{label}: process output {y} at sample {i}");
            }
        }
        (Err(e), Some(i)) => {
            assert_eq!(
                error_index(e),
                Some(i),
                "{label}: process failed with `{e}`, the trial loop at sample {i}"
            );
        }
        (Ok(()), Some(i)) => panic!(
            "{label}: process succeeded, the trial loop failed at sample {i} (x = {})",
            xs[i]
        ),
        (Err(e), None) => panic!("{label}: process failed (`{e}`), the trial loop did not"),
    }
    // the same committed state after either
    let last = xs
        .iter()
        .rev()
        .copied()
        .find(|x| x.is_finite())
        .unwrap_or(0.0);
    for x in [last, last + 0.25, last - 0.25, 0.0] {
        assert_eq!(
            probe(&mut a, x),
            probe(&mut b, x),
            "{label}: state after process vs after trial/commit (probe {x})"
        );
    }
    // replay after reset
    a.reset();
    let mut zs = vec![0.0; xs.len()];
    let replay = a.process(xs, &mut zs);
    match (&processed, &replay) {
        (Ok(()), Ok(())) => assert_eq!(bits(&zs), bits(&ys), "{label}: replay after reset"),
        (Err(e1), Err(e2)) => assert_eq!(
            error_index(e1),
            error_index(e2),
            "{label}: replay after reset fails elsewhere"
        ),
        _ => panic!("{label}: replay after reset: {processed:?} then {replay:?}"),
    }
}
