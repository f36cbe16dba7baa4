//! # hysteron-composition
//!
//! Combinators that build models from the operators of
//! `hysteron-operators`, each a small generic struct over its children
//! (static composition is inlined; `Box<dyn Operator>` children compose
//! the same way):
//!
//! | combinator | law |
//! |---|---|
//! | [`Cascade`] | `y = B[A[x]]` |
//! | [`Parallel`] | `y = A[x] + B[x]` |
//! | [`Scaled`] | `y = w · A[x]` |
//! | [`PiBank`] | `y = a0 x + Σ w_j play_{r_j}[x]` |
//! | [`PiInverse`] | `x = P⁻¹[y]` of a PI bank, again a PI bank (Krejčí–Kuhnen) |
//! | [`Feedback`] | `y = A[x − B[y]]`, solved each sample |
//! | [`MechanicalSeries`] | `F = L[x_L] = R[x_R]`, `x = x_L + x_R`, optional travel limits |
//! | [`Inverse`] | `u = A⁻¹[x]` for non-decreasing `A` |
//! | [`Oversample`] | `A` run at `q` sub-steps per sample, input interpolated linearly |
//!
//! The implicit ones share one solver ([`SolverOptions`]): a bracket search
//! then a safeguarded Newton iteration with bisection fallback.

#![warn(missing_docs)]
// The library promises never to panic on user input: no unwrap/expect/panic
// and no unchecked indexing outside tests (the lints are in the workspace
// Cargo.toml; each exception is an `allow` with the invariant that makes it safe).

mod cascade;
mod child;
mod delegate;
mod ext;
mod feedback;
mod feedback_lanes;
mod inverse;
mod oversample;
mod pair;
mod parallel;
mod pi_avx2;
mod pi_bank;
mod pi_inverse;
mod pi_lanes;
mod scaled;
mod series;
mod solve;

pub use cascade::Cascade;
pub use child::Child;
pub use ext::OperatorExt;
pub use feedback::Feedback;
pub use feedback_lanes::{MsdFeedback, MsdFeedbackLanes};
pub use inverse::Inverse;
pub use oversample::Oversample;
pub use parallel::Parallel;
pub use pi_bank::{PiBank, PiBankParams};
pub use pi_inverse::PiInverse;
pub use pi_lanes::PiLanes;
pub use scaled::Scaled;
pub use series::{MechanicalSeries, TravelLimits};
pub use solve::SolverOptions;

/// The operator crate, for the paths in this crate's exported macros.
#[doc(hidden)]
pub use hysteron_operators as __operators;
