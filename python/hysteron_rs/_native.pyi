"""Type stubs of the compiled module (checked by mypy's stubtest)."""

from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt
from typing_extensions import TypeAlias, final

__version__: str
__all__ = [
    "AnalysisError",
    "Band",
    "DescribingFunction",
    "Ensemble",
    "FitError",
    "FitResult",
    "HysteronError",
    "InputError",
    "LoopEnergy",
    "Model",
    "ParameterError",
    "SolverError",
    "SpecError",
    "__version__",
    "compare",
    "describing_function",
    "fit",
    "fit_records",
    "leaf",
    "leaf_kinds",
    "loop_energy",
    "paper_model",
    "run_batch",
    "run_parameter_sets",
    "sensitivity",
]

_ArrayLike: TypeAlias = Union[npt.ArrayLike, Sequence[float]]
_SpecLike: TypeAlias = Union[str, Mapping[str, Any]]

class HysteronError(ValueError):
    """Every error of hysteron_rs (a ValueError)."""
class SpecError(HysteronError):
    """A spec that is not valid JSON or not a spec; the message names the path in the document."""
class ParameterError(HysteronError):
    """A parameter outside its domain, a parameter vector of the wrong length, or an unknown or ambiguous parameter name."""
class InputError(HysteronError):
    """An input that is not a non-empty, finite, 1-D float array (the message names the sample)."""
class SolverError(HysteronError):
    """A model that failed while running: an implicit solve without a root, a jump, a non-finite output."""
class AnalysisError(HysteronError):
    """A describing-function or loop-energy analysis that could not run or did not reach a steady cycle."""
class FitError(HysteronError):
    """A fit that cannot start (empty or mismatched records, no free parameters, a bad option)."""

@final
class Model:
    """A hysteresis model: a spec (the tree of operators and its parameters)
    and the operator built from it, which holds the running state.

    * `run(x)` runs a float64 array from the current state and commits every
      sample; `step(x)` does one sample; `trial(x)` evaluates one sample
      without committing it, `commit()` keeps the last trial, `reset()`
      returns to the initial state.
    * `params` (a dict keyed by parameter path) and `with_params(...)`
      read and change parameters; `to_spec()` gives the spec as a dict.
    * `then`, `plus`, `scaled`, `series`, `feedback`, `inverse` and
      `oversample` compose models into new ones (from their initial states).

    Copies (`copy.copy`, `copy.deepcopy`) keep the running state and are
    independent; pickling goes through the spec, so an unpickled model
    starts from its initial state.
    """

    def __new__(cls, spec: _SpecLike) -> Model: ...
    @staticmethod
    def from_spec(spec: _SpecLike) -> Model:
        """A model from a spec: a dict (as `to_spec()` gives) or JSON text."""
    def to_spec(self) -> Dict[str, Any]:
        """The spec as a dict (JSON objects, lists and numbers)."""
    def to_json(self) -> str:
        """The spec as JSON text."""
    @property
    def name(self) -> str:
        """The operator's name (the spec's `type`)."""
    @property
    def param_names(self) -> List[str]:
        """The parameter paths, in the order of the flat parameter vector."""
    @property
    def params(self) -> Dict[str, float]:
        """The parameters as a dict keyed by parameter path (flat order)."""
    @property
    def tied_params(self) -> List[str]:
        """The parameters that are tied to another (a gap's `r0` and its
        spring's `z0`) and so cannot be changed or fitted on their own.
        """
    def with_params(
        self, values: Optional[Mapping[str, float]] = None, **kwargs: float
    ) -> Model:
        """A new model (from its initial state) with some parameters changed:
        `with_params({"r": 0.2})` or `with_params(r=0.2)`. A name is a full
        path or a suffix after a `.` that only one parameter has.
        """
    def with_dt(self, dt: float) -> Model:
        """The same model with the sample period of every rate-dependent node
        set to `dt` seconds (the nodes inside an `oversample` of `q`
        sub-steps get `dt / q`); from the initial state.
        """
    def run(
        self,
        x: _ArrayLike,
        *,
        dt: Optional[float] = None,
        time: Optional[_ArrayLike] = None,
    ) -> npt.NDArray[np.float64]:
        """Runs the model over `x` (a 1-D float array, or anything numpy turns
        into one) from its current state, committing every sample, and
        returns the outputs as a float64 array. The GIL is released while
        it runs. On an error the state is that before the failing sample.

        A rate-dependent model runs at the sample period of its spec, or at
        `dt` (seconds) or the step of `time` (uniformly spaced stamps, one
        per sample of `x`) where one is given: the model then keeps that
        period (see `dt`). A rate-independent model ignores both.
        """
    @property
    def dt(self) -> Optional[float]:
        """The sample period (s) a rate-dependent model runs at (`None` for a
        rate-independent model, and for one whose spec leaves it out until
        `run(x, dt=...)` or `with_dt` gives it).
        """
    def step(self, x: float) -> float:
        """One sample: `trial(x)` then `commit()`; returns the output."""
    def trial(self, x: float) -> float:
        """The output at input `x` from the committed state, without keeping
        it (a later `commit()` keeps the last trial).
        """
    def commit(self) -> None:
        """Keeps the state of the last `trial`."""
    def reset(self) -> None:
        """Returns to the initial state."""
    def then(self, other: Model) -> Model:
        """Cascade: `other` applied to this model's output."""
    def plus(self, other: Model) -> Model:
        """Parallel: the sum of both outputs."""
    def scaled(self, w: float) -> Model:
        """`w` times the output."""
    def series(
        self,
        other: Model,
        limits: Optional[Mapping[str, Any]] = None,
        solver: Optional[Mapping[str, Any]] = None,
    ) -> Model:
        """Mechanical series with `other`: equal force, displacements add.
        `limits` bounds this model's displacement: `None`,
        `{"type": "range", "lo": .., "hi": ..}` or
        `{"type": "gap", "b": .., "r0": ..}`; `solver` as in a spec.
        """
    def feedback(self, back: Model, solver: Optional[Mapping[str, Any]] = None) -> Model:
        """Negative feedback `y = self[x − back[y]]`, solved at every sample."""
    def inverse(self, solver: Optional[Mapping[str, Any]] = None) -> Model:
        """The numerical inverse of this (non-decreasing) model."""
    def oversample(self, q: int) -> Model:
        """This model run at `q ≥ 1` sub-steps per sample (input interpolated
        linearly), its rate-dependent nodes at `dt / q`.
        """
    def describe(self) -> str:
        """The spec as a short description (`describe` of the spec tree)."""
    def __copy__(self) -> Model: ...
    def __deepcopy__(self, memo: Any) -> Model: ...
    def __reduce__(self) -> Tuple[Any, Tuple[str]]: ...
    def __eq__(self, value: object, /) -> bool: ...

@final
class FitResult:
    """The outcome of `fit`: the fitted model and what the fit found.

    Standard errors come from the Gauss-Newton covariance
    `C = σ² (JᵀJ)⁻¹`, `σ² = Σ r² / (m − k)` (delta method through the
    reparametrization of bounded parameters); 95 % intervals are
    `θ ± 1.96 σ_θ` mapped back, so they respect the bounds.
    """

    @property
    def model(self) -> Model:
        """The model with the fitted parameters, in its initial state."""
    @property
    def dt(self) -> Optional[float]:
        """The sample period (s) the model ran at in the fit, `None` for a
        rate-independent model.
        """
    @property
    def free(self) -> List[str]:
        """The free parameters' paths, in the order of every per-parameter
        field.
        """
    @property
    def values(self) -> Dict[str, float]:
        """Fitted values, keyed by parameter path."""
    @property
    def start(self) -> Dict[str, float]:
        """Starting values, keyed by parameter path."""
    @property
    def std_errors(self) -> Dict[str, Optional[float]]:
        """Standard errors keyed by path (`None` where `JᵀJ` is singular, and
        for a parameter the output does not depend on at the solution).
        """
    @property
    def ci95(self) -> Dict[str, Optional[Tuple[float, float]]]:
        """95 % confidence intervals `(lo, hi)` keyed by path (`None` where
        `JᵀJ` is singular, and for a parameter the output does not depend on
        at the solution).
        """
    @property
    def correlation(self) -> Optional[npt.NDArray[np.float64]]:
        """The free parameters' correlation matrix (rows and columns in the
        order of `free`) as a 2-D array, or `None` where `JᵀJ` is singular
        (NaN in the row and column of a parameter the output does not
        depend on at the solution).
        """
    @property
    def condition_number(self) -> Optional[float]:
        """The condition number `λ_max/λ_min` of `JᵀJ` in the fit's internal
        parameters, or `None` where `JᵀJ` is singular.
        """
    @property
    def warnings(self) -> List[str]:
        """Identifiability warnings, one sentence each: every parameter the
        output does not depend on at the solution (a vanishing Jacobian
        column, such as a non-negative parameter driven to 0: no standard
        error), every parameter whose 95 % interval is wider than
        `|value|`, every pair correlated beyond 0.99, or a singular `JᵀJ`
        (empty when the data pin every free parameter down).
        """
    @property
    def starts(self) -> Optional[Dict[str, Any]]:
        """With `starts > 1`: a dict of `costs` (every start's final cost, in
        start order, `None` for a start that failed), `best` (the start
        kept) and `reached` (starts within 1 % of the best cost, or within
        1e-20 · ½Σy² of it, rounding: so a best cost of 0 counts too); else
        `None`.
        """
    @property
    def cost(self) -> float:
        """Final cost `½ Σ r²`."""
    @property
    def rms(self) -> float:
        """Root-mean-square residual."""
    @property
    def nrmse(self) -> Optional[float]:
        """`rms / RMS(y)`, `y`'s root mean square about zero (as `validate`
        and `compare` score); `None` for an output that is zero throughout.
        """
    @property
    def status(self) -> str:
        """`"converged"`, `"not_converged"` (the budget ran out) or `"failed"`."""
    @property
    def message(self) -> str:
        """Why the fit stopped."""
    @property
    def converged(self) -> bool:
        """True when a convergence criterion was met."""
    @property
    def iterations(self) -> int:
        """Levenberg-Marquardt iterations."""
    @property
    def evaluations(self) -> int:
        """Model simulations over the whole record."""
    @property
    def wall_time(self) -> float:
        """Wall time of the fit (s)."""
    @property
    def jacobian(self) -> str:
        """How the Jacobian was computed: `"exact"` (forward-mode derivatives)
        or `"fd"` (central finite differences, also where exact ones were
        asked for but the model has no dual twin).
        """
    @property
    def history(self) -> List[Dict[str, float]]:
        """One dict per iteration: `iteration`, `evaluations` (so far) and
        `cost` at the start of that iteration.
        """
    @property
    def records(self) -> List[Dict[str, Any]]:
        """Per record (in the order given): a dict of `samples` (compared),
        `rms` and `nrmse` (`rms / RMS(y)`, RMS about zero; `None` for an
        output that is zero throughout).
        """
    def predict_band(
        self,
        x: _ArrayLike,
        level: float = 0.95,
        method: str = "linearized",
        draws: int = 1000,
        seed: int = 0,
    ) -> Band:
        """The band of probability content `level` around the fitted model's
        output along `x` (from its initial state), from the covariance of
        the fitted shared parameters `C_ij = ρ_ij σ_i σ_j`.

        `method="linearized"`: `y_k ± z·√(g_kᵀ C g_k)`, `g_k = ∂y_k/∂θ`
        (exact, forward-mode), `z = Φ⁻¹((1 + level)/2)`.
        `method="monte_carlo"`: `draws` parameter vectors from `N(θ̂, C)`
        (generator seeded by `seed`) simulated, and the empirical quantiles
        `(1 ∓ level)/2` per sample of those that ran (`Band.failed_draws`
        counts the others). Per-record parameters and parameters without a
        standard error are held at their values. The GIL is released while
        it runs.
        """

@final
class Band:
    """An uncertainty band around a fitted model's output
    (`FitResult.predict_band`): per input sample, the fitted output and
    the band's edges.
    """

    @property
    def output(self) -> npt.NDArray[np.float64]:
        """The fitted model's output, one value per input sample."""
    @property
    def lower(self) -> npt.NDArray[np.float64]:
        """The band's lower edge, per sample."""
    @property
    def upper(self) -> npt.NDArray[np.float64]:
        """The band's upper edge, per sample."""
    @property
    def level(self) -> float:
        """The band's probability content, in (0, 1)."""
    @property
    def method(self) -> str:
        """`"linearized"` or `"monte_carlo"`."""
    @property
    def failed_draws(self) -> int:
        """Monte-Carlo draws that did not run (a parameter out of its domain,
        a model error), left out of the quantiles; 0 for `"linearized"`.
        """

@final
class DescribingFunction:
    """The first-harmonic gain of a model driven by `x = A sin θ` in its
    steady cycle: `N(A) = (b1 + i a1) / A` with `b1 = (1/π)∮ y sin θ dθ`,
    `a1 = (1/π)∮ y cos θ dθ`.
    """

    @property
    def amplitude(self) -> float:
        """The sine's amplitude `A`."""
    @property
    def re(self) -> float:
        """`Re N = b1 / A`."""
    @property
    def im(self) -> float:
        """`Im N = a1 / A` (negative for a lagging loop)."""
    @property
    def gain(self) -> float:
        """`|N|`."""
    @property
    def phase(self) -> float:
        """`arg N` (rad)."""
    @property
    def harmonics(self) -> List[Tuple[float, float]]:
        """`(a_k, b_k)` for `k = 0..harmonics` (cosine and sine coefficients)."""
    @property
    def change(self) -> float:
        """Relative change of the first harmonic over the last period."""

@final
class LoopEnergy:
    """The work a model's steady loop takes per cycle under `x = A sin θ`."""

    @property
    def amplitude(self) -> float:
        """The sine's amplitude `A`."""
    @property
    def work(self) -> float:
        """`W = ∮ y dx` over one steady cycle (trapezoid rule): positive for a
        clockwise loop (stop, elastoplastic, MMS, Bouc-Wen), negative for a
        counterclockwise one (play, PI bank); `area` is `|W|`.
        """
    @property
    def change(self) -> float:
        """Relative change of the first harmonic over the last period."""
    @property
    def area(self) -> float:
        """The loop area `|W|`, the energy dissipated per cycle whatever the
        loop's orientation.
        """

@final
class Ensemble:
    """`N` instances of a model's structure, instance `i` with the parameter
    vector `params[i]` (columns in the order of `model.param_names`): play and MMS
    leaves, PI banks of fewer than 64 plays not a multiple of eight, a
    Bouc-Wen spring whose rows all have `n = 1`, and the
    Bouc-Wen benchmark system (a mass-spring-damper with such a spring fed
    back, oversampled or not) step eight instances per vector instruction,
    any other model
    one instance at a time, in parallel. Every instance gives the bits the
    model gives alone with its parameters.
    """

    def __new__(cls, model: Model, params: _ArrayLike) -> Ensemble:
        """`model` with one instance per row of `params` (a 2-D float array of
        `len(model.param_names)` columns). A row out of the parameters' domains
        is that instance's error when run, not an error here.
        """
    def __len__(self) -> int:
        """The number of instances."""
    @property
    def names(self) -> List[str]:
        """The parameter names: the columns of `params`."""
    @property
    def kernel(self) -> str:
        """How the instances are stepped: the leaf of the lane kernel
        (`"play"`, `"mms"`, `"bouc_wen"`, `"msd_feedback"`), or `"instances"`
        (one at a time).
        """
    def run(self, x: _ArrayLike, *, errors: str = "raise", threads: Optional[int] = None) -> npt.NDArray[np.float64]:
        """Runs every instance from its initial state over `x` (1-D) and
        returns the outputs, shape `(len(self), len(x))`. With
        `errors="raise"` the first failing instance raises its typed error
        (its `index` the instance); with `errors="nan"` a failing
        instance's row is NaN and the others are returned. The instances
        run on `threads` threads (default: one per core); the GIL is
        released while they run.
        """

def leaf_kinds() -> List[Dict[str, Any]]:
    """Every registered leaf: a list of dicts `{"type", "equation", "doc",
    "example", "fields": [{"name", "kind", "doc", "required"}]}`, fields in
    declaration order, `doc` the constructor's docstring (rendered by
    `hysteron::models::spec::reference`), `example` a valid parameter dict;
    a field is not `required` when the spec may leave it out (it has a
    default, or it is the sample period `dt` that the data may give);
    `kind` is `"param"`, `"nested"` or `"fixed"` (a setting, not a
    parameter).
    """
def leaf(kind: str, params: Mapping[str, Any]) -> Model:
    """The leaf `kind` with the parameters `params` (a dict as in a spec)."""
def paper_model() -> Model:
    """The paper's transmission model (a `transmission` spec) with its
    default parameters; change them with `with_params`.
    """
def describing_function(
    model: Model,
    amplitude: float,
    *,
    samples_per_period: int = 1024,
    settle_periods: int = 20,
    steady_tol: float = 1e-9,
    harmonics: int = 5,
) -> DescribingFunction:
    """The describing function of `model` (from its initial state) at
    amplitude `amplitude`: the sine is run until its cycle is periodic to
    `steady_tol`, at most `settle_periods` periods.
    """
def loop_energy(
    model: Model,
    amplitude: float,
    *,
    samples_per_period: int = 1024,
    settle_periods: int = 20,
    steady_tol: float = 1e-9,
) -> LoopEnergy:
    """The loop work of `model` (from its initial state) under a sine of
    amplitude `amplitude` in its steady cycle (options as for
    `describing_function`).
    """
def fit(
    model: Model,
    x: _ArrayLike,
    y: _ArrayLike,
    free: Sequence[str],
    *,
    dt: Optional[float] = None,
    time: Optional[_ArrayLike] = None,
    patience: int = 200,
    stride: int = 1,
    ftol: float = 1e-12,
    xtol: float = 1e-12,
    gtol: float = 0.0,
    max_evaluations: Optional[int] = None,
    max_seconds: Optional[float] = None,
    starts: int = 1,
    spread: float = 1.3862943611198906,
    seed: int = 0,
    jacobian: str = "exact",
) -> FitResult:
    """Fits the parameters `free` (full paths or unique suffixes) of `model`
    to the record `(x, y)`: residuals `model(x) − y` from the model's
    initial state, Levenberg-Marquardt with exact Jacobians (forward-mode
    derivatives; `jacobian="fd"` for central finite differences), bounded
    parameters through a reparametrization that keeps them inside
    their domains. The other parameters stay at the model's values. The
    GIL is released while it runs.

    `patience` bounds the trial steps (`patience · (k + 1)`, each accepted
    one followed by a Jacobian: one pass over dual numbers per 8 parameters,
    or `2k` simulations by finite differences); `max_evaluations` and
    `max_seconds` bound the work for real (the fit then ends not converged
    at its best point); `stride` compares every `stride`-th output with `y`
    (`len(x) = stride · len(y)`). `starts > 1` fits from the model's values
    and `starts − 1` Latin-hypercube points around them (within a factor
    `e^spread` for a positive parameter; `seed` fixes them), in parallel,
    and keeps the best (`FitResult.starts` says how many reached it).

    A rate-dependent model runs at its spec's sample period, or at `dt`
    (seconds) or the step of `time` (uniformly spaced stamps, one per
    sample of `x`) where one is given; `FitResult.dt` says which.
    """
def fit_records(
    model: Model,
    records: Sequence[Tuple[_ArrayLike, _ArrayLike]],
    free: Sequence[str],
    *,
    own: Sequence[str] = ...,
    skip: int = 0,
    dt: Optional[float] = None,
    patience: int = 200,
    stride: int = 1,
    ftol: float = 1e-12,
    xtol: float = 1e-12,
    gtol: float = 0.0,
    max_evaluations: Optional[int] = None,
    max_seconds: Optional[float] = None,
    starts: int = 1,
    spread: float = 1.3862943611198906,
    seed: int = 0,
    jacobian: str = "exact",
) -> FitResult:
    """Fits one parameter set to several records `[(x, y), …]`, each simulated
    from the model's initial state; `own` names parameters fitted
    separately for each record (an initial state, a preload: keyed
    `"path[record i]"` in the result), `skip` leading output samples of
    each record are simulated but not compared (a warm-up); `dt` gives
    the sample period of every record (seconds). Otherwise as `fit`.
    """
def run_batch(
    model: Model, records: Sequence[_ArrayLike], *, threads: Optional[int] = None
) -> List[npt.NDArray[np.float64]]:
    """Runs `model` from its initial state over each record (a list of 1-D
    float arrays), in parallel on `threads` threads (default: one per
    core); returns the outputs in order. An error names the record
    (`index`) and the sample.
    """
def run_parameter_sets(
    model: Model,
    sets: Sequence[Mapping[str, float]],
    x: _ArrayLike,
    *,
    threads: Optional[int] = None,
) -> List[npt.NDArray[np.float64]]:
    """Runs `model` over `x` once per parameter set (each a dict of changed
    values keyed by path or unique suffix, the rest as in `model`), from
    the initial state, in parallel; returns the outputs in order.
    """
def sensitivity(
    model: Model, x: _ArrayLike, params: Sequence[str]
) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Runs `model` from its initial state over `x` and returns `(y, dydp)`:
    the output (1-D float64 array) and its derivatives with respect to the
    parameters `params` (full paths or unique suffixes, each at most once),
    a 2-D float64 array of shape `(len(x), len(params))` whose column `i`
    is `∂y/∂params[i]`. The derivatives are forward-mode automatic
    differentiation (dual numbers: no step size; at a kink, the derivative
    of the branch the model takes). The GIL is released while it runs.
    """
def compare(
    candidates: Sequence[Mapping[str, Any]],
    train: Sequence[Tuple[_ArrayLike, _ArrayLike]],
    validate: Optional[Sequence[Tuple[_ArrayLike, _ArrayLike]]] = None,
    *,
    cross_validate: Optional[int] = None,
    skip: int = 0,
    dt: Optional[float] = None,
    lowpass: Optional[float] = None,
    patience: int = 200,
    max_seconds: Optional[float] = None,
    starts: int = 1,
    spread: float = 1.3862943611198906,
    seed: int = 0,
) -> List[Dict[str, Any]]:
    """Compares candidate structures: each candidate, a dict
    `{"name": str, "model": Model, "free": [names], "own": [names]}`
    (`own` optional: parameters fitted per training record), is fitted on
    the `train` records `[(x, y), …]` as `fit_records` fits it, and scored
    on the `validate` records by its held-out NRMSE (RMS error over the RMS
    of the measured output, from sample `skip` on), and with `lowpass`
    (Hz; needs `dt`) after a zero-phase 4th-order Butterworth low-pass of
    both signals. With `cross_validate=K` instead of `validate`, each
    training record is scored by the fit on the folds without it (record
    `i` in fold `i mod K`).

    Returns one dict per candidate, best first, with the keys of
    `hysteron compare --csv` (`rank`, `candidate`, `k`, `n`,
    `training_cost`, `aic`, `bic`, `heldout_nrmse_mean`,
    `heldout_nrmse_worst`, `heldout_lowpassed_mean`,
    `heldout_lowpassed_worst`, `p_vs_next`, `converged`, `error`) and the
    per-record `heldout_nrmse`, `heldout_lowpassed` and the fitted `model`;
    `pandas.DataFrame(rows)` makes it a table. The ranking is by the
    held-out mean (low-passed with `lowpass`); `p_vs_next` is a two-sided
    sign test against the next rank over the per-record errors. A
    candidate whose fit or score fails has its `error` and no rank; the
    others go on. The GIL is released while the candidates run (in
    parallel).
    """
