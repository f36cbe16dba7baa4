"""hy.Ensemble: every instance is the model alone with its parameters, bit
for bit, on the lane kernels and one instance at a time; failures are
typed errors naming the instance, or NaN rows on request."""

import pathlib

import numpy as np
import pytest

import hysteron_rs as hy


def _walk(n: int) -> np.ndarray:
    rng = np.random.default_rng(7)
    steps = rng.normal(0.0, 0.05, n)
    steps[::13] = 0.0  # holds
    return np.cumsum(steps)


def _alone(model: hy.Model, row: np.ndarray, x: np.ndarray) -> np.ndarray:
    return model.with_params(dict(zip(model.param_names, row))).run(x)


@pytest.mark.parametrize(
    "model, kernel",
    [
        (hy.mms(1.0, 20.0), "mms"),
        (hy.play(0.3), "play"),
        (hy.pi_bank(0.2, [0.0, 0.3, 0.7, 1.2, 1.5], [1.0, 0.6, -0.2, 0.3, 0.1]), "pi_bank"),
        (hy.pi_bank(0.2, [0.1 * k for k in range(8)], [1.0 / (1 + k) for k in range(8)]), "instances"),
        (hy.play(0.3).then(hy.dead_zone(-0.2, 0.4)), "instances"),
    ],
)
def test_each_instance_is_the_model_alone(model: hy.Model, kernel: str) -> None:
    base = np.array([model.params[n] for n in model.param_names])
    rows = base * (1.0 + 0.05 * np.arange(13)[:, None] / 13.0)
    ensemble = hy.Ensemble(model, rows)
    assert ensemble.kernel == kernel
    assert len(ensemble) == 13 and ensemble.names == model.param_names
    x = _walk(700)
    y = ensemble.run(x)
    assert y.shape == (13, 700) and y.dtype == np.float64
    for i, row in enumerate(rows):
        assert np.array_equal(y[i], _alone(model, row, x)), i
    # on one thread, or two: the same bits
    assert np.array_equal(ensemble.run(x, threads=1), y)
    assert np.array_equal(ensemble.run(x, threads=2), y)


def test_the_benchmark_system_steps_in_lanes(root: pathlib.Path) -> None:
    """The Bouc-Wen benchmark system (a mass-spring-damper with the spring
    fed back, oversampled) with its parameters spread, the spring's
    exponent kept at 1: the lane kernel, each row the model alone."""
    model = hy.Model.from_spec((root / "examples" / "specs" / "boucwen-benchmark.json").read_text())
    names = model.param_names
    base = np.array([model.params[n] for n in names])
    rows = base * (1.0 + 0.05 * np.arange(9)[:, None] / 9.0)
    rows[:, [i for i, n in enumerate(names) if n.endswith(".n")]] = 1.0
    ensemble = hy.Ensemble(model, rows)
    assert ensemble.kernel == "msd_feedback"
    x = 30.0 * np.sin(np.linspace(0.0, 20.0, 400)) + _walk(400)
    y = ensemble.run(x)
    for i, row in enumerate(rows):
        assert np.array_equal(y[i], _alone(model, row, x)), i


def test_a_failing_instance_is_named_or_nan() -> None:
    model = hy.play(0.3)
    rows = np.array([[0.1, 0.0], [-0.5, 0.0], [0.2, 0.0]])
    ensemble = hy.Ensemble(model, rows)
    with pytest.raises(hy.ParameterError, match="instance 1: ") as err:
        ensemble.run([0.0, 1.0])
    assert err.value.index == 1
    y = ensemble.run([0.0, 1.0], errors="nan")
    assert np.isnan(y[1]).all() and np.isfinite(y[[0, 2]]).all()


def test_bad_shapes_and_inputs_are_typed_errors() -> None:
    model = hy.mms(1.0, 20.0)
    with pytest.raises(hy.InputError, match="3 parameters"):
        hy.Ensemble(model, np.ones((4, 2)))
    with pytest.raises(hy.InputError, match="params: must be 2-D"):
        hy.Ensemble(model, np.ones(3))
    with pytest.raises(hy.InputError, match="params: is empty"):
        hy.Ensemble(model, np.ones((0, 3)))
    ensemble = hy.Ensemble(model, np.ones((2, 3)))
    with pytest.raises(hy.InputError, match="sample 1"):
        ensemble.run([0.0, np.nan])
    with pytest.raises(hy.InputError, match="errors: must be"):
        ensemble.run([0.0], errors="ignore")
    with pytest.raises(hy.InputError, match="threads: must be at least 1"):
        ensemble.run([0.0], threads=0)
