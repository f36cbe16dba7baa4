//! What the Bouc-Wen laws whose state is the hysteretic displacement and
//! energy `(z, e)` share ([`BoucWenDegrading`](crate::BoucWenDegrading),
//! [`Bwbn`](crate::Bwbn)): the state, and one sample's step, which
//! integrates
//!
//! `dz/dx = rate(ẋ, z, e)`,  `de/dx = (1 − α) k0 z`,
//! `F = α k0 x + (1 − α) k0 z`,
//!
//! over the input's travel by adaptive Dormand–Prince
//! ([`dopri5`](crate::ode)), side by side of `z = 0`.

use crate::ode::dopri5;
use crate::{Declared, Domain, FieldInfo, Float, ParamSet, Result, Trial};

/// Declares the parameters of a member of OpenSees' Bouc-Wen family
/// (`alpha ko n gamma beta Ao`, written `alpha k0 n gamma beta a0`,
/// followed by the member's own fields), as
/// [`declare_params!`](crate::declare_params) does, and their
/// [`FamilyBase`]: the six shared parameters are written once, here.
macro_rules! bouc_wen_family_params {
    (
        $(#[$sm:meta])*
        pub struct $name:ident<T>: Copy { $($own:tt)* }
        $($rest:tt)*
    ) => {
        $crate::declare_params! {
            $(#[$sm])*
            pub struct $name<T>: Copy {
                /// Ratio `α` of the post-yield to the initial stiffness (finite).
                alpha: T => Real = 0.1,
                /// Initial stiffness `k0 > 0`.
                k0: T => Positive = 10.0,
                /// Sharpness of the transition `n ≥ 1`.
                n: T => AtLeast(1.0) = 1.0,
                /// `γ` (finite): the loop's shape, with `β`.
                gamma: T => Real = 0.5,
                /// `β` (finite): the loop's shape, with `γ`; `β + γ > 0`
                /// bounds the hysteretic displacement (`bwbn` requires it).
                beta: T => Real = 0.5,
                /// `a0 > 0`, the initial `A`: the hysteretic stiffness
                /// `(1 − α) k0 A`.
                a0: T => Positive = 1.0,
                $($own)*
            }
            $($rest)*
        }

        impl<T: $crate::Float> $crate::energy_flow::FamilyBase<T> for $name<T> {
            fn alpha(&self) -> T {
                self.alpha
            }

            fn k0(&self) -> T {
                self.k0
            }

            fn gamma(&self) -> T {
                self.gamma
            }

            fn beta(&self) -> T {
                self.beta
            }
        }
    };
}
pub(crate) use bouc_wen_family_params;

/// The [`StepLaw`](crate::StepLaw) of a law on `(z, e)`: it starts at
/// rest and steps by `step` (`fn(&law, &state, x)`):
/// [`EnergyFlow::energy_step`] for the force, [`observe_energy`] for the
/// energy.
macro_rules! energy_step_law {
    ($law:ty, $step:path) => {
        impl<T: $crate::Float> $crate::StepLaw<T> for $law {
            type State = $crate::EnergyState<T>;
            const RESTS_WHEN_HELD: bool = true;

            fn initial(&self) -> $crate::EnergyState<T> {
                $crate::EnergyState::at_rest()
            }

            fn step(
                &self,
                s: &$crate::EnergyState<T>,
                x: T,
            ) -> $crate::Result<($crate::EnergyState<T>, $crate::Trial<T>)> {
                $step(self, s, x)
            }
        }
    };
}
pub(crate) use energy_step_law;

/// The state between samples: the input `x` reached, the hysteretic
/// displacement `z`, and the energy `e = ∫ (1 − α) k0 z dx`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyState<T> {
    /// The input of the last sample.
    pub x: T,
    /// Hysteretic displacement `z`.
    pub z: T,
    /// Hysteretic energy `e` (the integral of the hysteretic force over
    /// the input: over a closed loop, the energy it dissipated).
    pub e: T,
}

impl<T: Float> EnergyState<T> {
    /// At rest: `x = z = e = 0`.
    pub(crate) fn at_rest() -> Self {
        EnergyState {
            x: T::zero(),
            z: T::zero(),
            e: T::zero(),
        }
    }
}

/// The local error held per sub-step, relative to the state's scale.
const RTOL: f64 = 1e-11;

/// The parameters every member of the Bouc-Wen family has.
pub(crate) trait FamilyBase<T: Float> {
    /// Post-yield stiffness ratio `α`.
    fn alpha(&self) -> T;
    /// Initial stiffness `k0`.
    fn k0(&self) -> T;
    /// `γ`.
    fn gamma(&self) -> T;
    /// `β`.
    fn beta(&self) -> T;

    /// The loop's shape factor on the branch taken: `γ + β` while loading
    /// (travelling in direction `dir` on the side `positive` of `z = 0`
    /// away from it, `ẋ z > 0`), else `γ − β`.
    #[inline(always)]
    fn shape(&self, dir: T, positive: bool) -> T {
        if (dir > T::zero()) == positive {
            self.gamma() + self.beta()
        } else {
            self.gamma() - self.beta()
        }
    }
}

/// A Bouc-Wen law on `(z, e)`.
pub(crate) trait EnergyFlow<T: Float>: FamilyBase<T> + Declared<T> {
    /// The scale of `z` (its ultimate value) for the error control.
    fn z_scale(&self) -> f64;
    /// `dz/dx` at `(z, e)` travelling in direction `dir` (`±1`), on the
    /// side `positive` of `z = 0`: the side, not the sign of `z`, picks the
    /// branch (`γ ± β`, the sign of `|z|`), so that a state a rounding error
    /// across `z = 0` keeps its side's flow and derivatives.
    fn rate(&self, dir: T, positive: bool, z: T, e: T) -> T;

    /// The side of `z = 0` the state is on: the sign of `z` beyond `snap`,
    /// else the side `z` moves into (where both sides' flows agree).
    fn side(&self, dir: T, z: T, e: T, snap: f64) -> bool {
        if z.as_f64().abs() > snap {
            z > T::zero()
        } else {
            dir * self.rate(dir, true, z, e) > T::zero()
        }
    }

    /// One sample from `s` to the input `x`: `(z, e)` integrated over the
    /// travel `|x − s.x|` (each sub-step's local error below `1e-11` of the
    /// state's scale, and ending where `z` changes sign), the output
    /// `F = α k0 x + (1 − α) k0 z` and its tangent `α k0 + (1 − α) k0 dz/dx`
    /// at the end, in the direction travelled.
    fn energy_step(&self, s: &EnergyState<T>, x: T) -> Result<(EnergyState<T>, Trial<T>)> {
        let (alpha, k0) = (self.alpha(), self.k0());
        let hysteretic = (T::one() - alpha) * k0;
        let travel = x - s.x;
        let dir = if travel < T::zero() {
            -T::one()
        } else {
            T::one()
        };
        let zs = self.z_scale();
        let snap = 1e-8 * zs;
        let [z, e] = if travel == T::zero() {
            [s.z, s.e]
        } else {
            let energy_scale = hysteretic.as_f64().abs();
            dopri5(
                |y: &[T; 2], positive| {
                    [
                        dir * self.rate(dir, positive, y[0], y[1]),
                        dir * hysteretic * y[0],
                    ]
                },
                (
                    |y: &[T; 2]| self.side(dir, y[0], y[1], snap),
                    |y: &[T; 2]| y[0].as_f64(),
                    snap,
                ),
                [s.z, s.e],
                travel.abs(),
                |y| {
                    let z = y[0].as_f64().abs().max(zs);
                    [z, y[1].as_f64().abs().max(energy_scale * z * zs)]
                },
                RTOL,
                Self::KIND,
            )?
        };
        let dz = self.rate(dir, self.side(dir, z, e, 0.0), z, e);
        Ok((
            EnergyState { x, z, e },
            Trial {
                output: alpha * k0 * x + hysteretic * z,
                tangent: alpha * k0 + hysteretic * dz,
            },
        ))
    }
}

/// A Bouc-Wen law on `(z, e)` with its hysteretic energy `e` as the
/// output instead of the force: the same parameters (and the same JSON
/// form), the same step; the tangent is `de/dx = (1 − α) k0 z`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct Energy<P>(pub P);

impl<T: Float, P: ParamSet<T>> ParamSet<T> for Energy<P> {
    const FIELDS: &'static [FieldInfo] = P::FIELDS;
    fn count(&self) -> usize {
        self.0.count()
    }
    fn names_into(&self, prefix: &str, out: &mut Vec<String>) {
        self.0.names_into(prefix, out)
    }
    fn domains_into(&self, out: &mut Vec<Domain>) {
        self.0.domains_into(out)
    }
    fn write(&self, out: &mut Vec<T>) {
        self.0.write(out)
    }
    fn read(&self, p: &mut &[T]) -> Result<Self> {
        self.0.read(p).map(Energy)
    }
    fn validate(&self) -> Result<()> {
        self.0.validate()
    }
    fn example() -> Self {
        Energy(P::example())
    }
}

/// The step of `law`, observed through its energy.
pub(crate) fn observe_energy<T: Float, P: EnergyFlow<T>>(
    Energy(law): &Energy<P>,
    s: &EnergyState<T>,
    x: T,
) -> Result<(EnergyState<T>, Trial<T>)> {
    let (next, _) = law.energy_step(s, x)?;
    let hysteretic = (T::one() - law.alpha()) * law.k0();
    let trial = Trial {
        output: next.e,
        tangent: hysteretic * next.z,
    };
    Ok((next, trial))
}

/// Declares the energy output of a law on `(z, e)`: its kind, equation,
/// cast and step.
macro_rules! energy_output {
    ($params:ident, $kind:literal, $equation:literal) => {
        impl<T: $crate::Float> $crate::Declared<T> for $crate::energy_flow::Energy<$params<T>> {
            const KIND: &'static str = $kind;
            const EQUATION: &'static str = $equation;
            type With<U: $crate::Float> = $crate::energy_flow::Energy<$params<U>>;

            fn cast_law<U: $crate::Float>(&self) -> Self::With<U> {
                $crate::energy_flow::Energy($crate::CastScalar::<U>::cast_scalar(&self.0))
            }
        }

        $crate::energy_flow::energy_step_law!(
            $crate::energy_flow::Energy<$params<T>>,
            $crate::energy_flow::observe_energy
        );
    };
}
pub(crate) use energy_output;

/// `|z|^n` on the side `positive` of `z = 0`: `z` or `−z` (so a rounding
/// error across 0 keeps the side's derivative) for `n = 1`, else that
/// size to the `n`, 0 where it is not positive.
#[inline(always)]
pub(crate) fn power_on_side<T: Float>(positive: bool, z: T, n: T) -> T {
    let size = if positive { z } else { -z };
    if n == T::one() {
        size
    } else if size > T::zero() {
        size.powf(n)
    } else {
        T::zero()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::Energy;
    use crate::test_support::step_difference;
    use crate::{
        BoucWenDegrading, BoucWenDegradingEnergy, BoucWenDegradingParams, Bwbn, BwbnEnergy,
        BwbnParams, Operator, ParamSet,
    };

    /// A random walk from 0 (xorshift, steps of up to 0.15), with a jump
    /// every 200 samples.
    fn walk(seed: u64, n: usize) -> Vec<f64> {
        let mut s = seed;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut x = 0.0_f64;
        (0..n)
            .map(|i| {
                x = if i % 200 == 199 {
                    6.0 * next() - 3.0
                } else {
                    (x + 0.3 * next() - 0.15).clamp(-3.0, 3.0)
                };
                x
            })
            .collect()
    }

    /// The energy `e` of each step of `op` over `x`.
    fn energies<O: Operator<f64>>(mut op: O, x: &[f64], e: impl Fn(&O) -> f64) -> Vec<f64> {
        x.iter()
            .map(|&v| {
                op.trial(v).unwrap();
                op.commit();
                e(&op)
            })
            .collect()
    }

    /// What the models promise of their hysteretic energy where `β ≥ |γ|`
    /// (a dissipative loop): from rest it is never negative, and over every
    /// closed cycle (the input back where it was) it does not fall.
    #[test]
    fn hysteretic_energy_is_non_negative_and_grows_over_closed_cycles() {
        let cycle: Vec<f64> = (0..600)
            .map(|i| 2.5 * (std::f64::consts::TAU * i as f64 / 200.0).sin())
            .collect();
        for n in [1.0, 2.0] {
            let bwbn = Bwbn::from_params(BwbnParams {
                n,
                ..BwbnParams::example()
            })
            .unwrap();
            let degrading = BoucWenDegrading::from_params(BoucWenDegradingParams {
                n,
                ..Default::default()
            })
            .unwrap();
            for seed in 1..6 {
                let x = walk(seed, 3000);
                let e = energies(bwbn.clone(), &x, |op| op.state().e);
                let f = energies(degrading.clone(), &x, |op| op.state().e);
                for (i, (a, b)) in e.iter().zip(&f).enumerate() {
                    assert!(
                        *a >= 0.0 && *b >= 0.0,
                        "n = {n}, seed {seed}, sample {i}: {a} {b}"
                    );
                }
            }
            // one sample per period is the same input: the closed cycles
            let e = energies(bwbn.clone(), &cycle, |op| op.state().e);
            let f = energies(degrading.clone(), &cycle, |op| op.state().e);
            for k in 1..3 {
                let (i, j) = (200 * k - 1, 200 * (k + 1) - 1);
                assert!(e[j] > e[i] && f[j] > f[i], "n = {n}, cycle {k}");
            }
        }
    }

    /// The energy outputs are the force models' energy, bit for bit, and
    /// their tangent is the derivative of the energy in the input.
    #[test]
    fn the_energy_outputs_are_the_models_energy() {
        let x = walk(9, 2000);
        let bwbn = BwbnParams::example();
        let degrading = BoucWenDegradingParams::default();
        let e = energies(Bwbn::from_params(bwbn).unwrap(), &x, |op| op.state().e);
        let f = energies(
            BoucWenDegrading::from_params(degrading).unwrap(),
            &x,
            |op| op.state().e,
        );
        let ys = BwbnEnergy::from_params(Energy(bwbn))
            .unwrap()
            .run(&x)
            .unwrap();
        let zs = BoucWenDegradingEnergy::from_params(Energy(degrading))
            .unwrap()
            .run(&x)
            .unwrap();
        for i in 0..x.len() {
            assert_eq!(
                (ys[i].to_bits(), zs[i].to_bits()),
                (e[i].to_bits(), f[i].to_bits()),
                "sample {i}"
            );
        }
        let law = Energy(bwbn);
        let mut op = BwbnEnergy::from_params(law).unwrap();
        for (i, &v) in x.iter().enumerate().take(400) {
            let s = *op.state();
            let t = op.trial(v).unwrap();
            if (v - s.x).abs() > 1e-3 {
                let fd = step_difference(&law, &s, v, 1e-6 * (v - s.x).signum());
                assert!(
                    (t.tangent - fd).abs() < 1e-5 * fd.abs().max(1.0),
                    "sample {i}: {} vs {fd}",
                    t.tangent
                );
            }
            op.commit();
        }
    }
}
