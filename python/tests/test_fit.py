"""fit: recovering known parameters, the result object, its errors."""

from __future__ import annotations

import numpy as np
import pytest

import hysteron_rs as hy


def _record(n: int = 4000) -> np.ndarray:
    t = np.linspace(0.0, 1.0, n)
    return 2.0 * np.exp(-2.0 * t) * np.sin(2 * np.pi * 8 * t)


def test_noise_free_recovery_of_a_bouc_wen_spring() -> None:
    truth = hy.bouc_wen(0.3, 1.0, 0.8, 0.4, 1.5, stiffness={"z": [0.0], "s": [3.0]})
    x = _record()
    y = truth.run(x)
    start = truth.with_params(w=0.4, beta=0.6, gamma=0.5)
    result = hy.fit(start, x, y, ["w", "beta", "gamma"])
    assert result.converged and result.status == "converged", result.message
    for name, value in result.values.items():
        want = truth.params[name]
        assert abs(value - want) <= 1e-6 * abs(want), (name, value, want)
    assert result.free == ["w", "beta", "gamma"]
    assert result.start == {"w": 0.4, "beta": 0.6, "gamma": 0.5}
    assert result.rms < 1e-8
    assert result.model.params == pytest.approx(truth.params, rel=1e-6)
    assert np.allclose(result.model.run(x), y, atol=1e-7)
    hist = result.history
    assert len(hist) >= 1 and hist[-1]["cost"] <= hist[0]["cost"]
    assert "converged" in str(result)
    assert result.jacobian == "exact"


def test_exact_and_finite_difference_jacobians_reach_the_same_fit() -> None:
    truth = hy.bouc_wen(0.3, 1.0, 0.8, 0.4, 1.5, stiffness={"z": [0.0], "s": [3.0]})
    x = _record()
    y = truth.run(x)
    start = truth.with_params(w=0.4, beta=0.6, gamma=0.5)
    exact = hy.fit(start, x, y, ["w", "beta", "gamma"], jacobian="exact")
    fd = hy.fit(start, x, y, ["w", "beta", "gamma"], jacobian="fd")
    assert (exact.jacobian, fd.jacobian) == ("exact", "fd")
    for name, value in fd.values.items():
        assert exact.values[name] == pytest.approx(value, rel=1e-8), name
    # A Jacobian by finite differences runs two simulations per parameter,
    # an exact one a single pass over dual numbers.
    assert exact.evaluations < fd.evaluations


def test_noisy_fit_reports_uncertainty_and_correlation() -> None:
    truth = hy.mms(1.5, 20.0)
    x = _record()
    rng = np.random.default_rng(1)
    y = truth.run(x) + 0.01 * rng.standard_normal(x.size)
    result = hy.fit(hy.mms(1.0, 10.0), x, y, ["f_c", "k"])
    se = result.std_errors
    for name in ("f_c", "k"):
        lo, hi = result.ci95[name]
        assert lo < result.values[name] < hi
        assert se[name] is not None and se[name] > 0
        assert lo < truth.params[name] < hi  # 95 %: this seed's interval holds the truth
    c = result.correlation
    assert c is not None and c.shape == (2, 2)
    assert np.allclose(np.diag(c), 1.0) and np.allclose(c, c.T)
    assert result.nrmse is not None and result.nrmse < 0.05
    k = result.condition_number
    assert k is not None and 1.0 <= k < 1e6
    assert result.warnings == []


def test_parameters_the_data_do_not_determine_are_named_in_the_warnings() -> None:
    # Two gains in parallel: only their sum is determined.
    x = _record()
    start = hy.Model.from_spec(
        {"type": "parallel", "left": {"type": "gain", "k": 2.0}, "right": {"type": "gain", "k": 0.5}}
    )
    result = hy.fit(start, x, 1.5 * x, ["left.gain.k", "right.gain.k"])
    assert result.warnings, str(result)
    # correlated or singular, the warning names both
    assert any("`left.gain.k`" in w and "`right.gain.k`" in w for w in result.warnings), result.warnings
    assert "warning: " in str(result)


def test_several_starts_find_what_one_start_misses() -> None:
    # A play's threshold from beyond the input's amplitude: the output never
    # moves there, so one start stays; a Latin hypercube of 8 starts finds it.
    x = np.sin(np.linspace(0.0, 20.0, 800))
    y = hy.play(0.3).run(x)
    one = hy.fit(hy.play(2.0), x, y, ["r"])
    assert one.values["r"] == 2.0 and one.starts is None
    many = hy.fit(hy.play(2.0), x, y, ["r"], starts=8, seed=1)
    assert abs(many.values["r"] - 0.3) < 1e-9
    st = many.starts
    assert st is not None and len(st["costs"]) == 8 and 1 <= st["reached"] < 8
    assert st["best"] != 0
    again = hy.fit_records(hy.play(2.0), [(x, y)], ["r"], starts=8, seed=1)
    assert again.values == many.values
    with pytest.raises(hy.FitError, match="starts"):
        hy.fit(hy.play(2.0), x, y, ["r"], starts=0)
    with pytest.raises(hy.FitError, match="spread"):
        hy.fit(hy.play(2.0), x, y, ["r"], starts=2, spread=float("nan"))


def test_fit_errors() -> None:
    m = hy.mms(1.0, 10.0)
    x = _record(100)
    y = m.run(x)
    with pytest.raises(hy.ParameterError, match="unknown parameter"):
        hy.fit(m, x, y, ["nope"])
    with pytest.raises(hy.FitError, match="no free parameters"):
        hy.fit(m, x, y, [])
    with pytest.raises(hy.FitError, match="input has 100 samples, output 99"):
        hy.fit(m, x, y[:-1], ["k"])
    with pytest.raises(hy.FitError, match="output sample 3 is not finite"):
        bad = y.copy()
        bad[3] = np.nan
        hy.fit(m, x, bad, ["k"])
    with pytest.raises(hy.ParameterError, match="named twice"):
        hy.fit(m, x, y, ["k", "k"])
    with pytest.raises(hy.ParameterError, match="tied"):
        hy.fit(hy.paper_model(), x, x, ["right.bouc_wen.z0"])
    with pytest.raises(hy.FitError, match="patience"):
        hy.fit(m, x, y, ["k"], patience=0)
    with pytest.raises(ValueError, match="jacobian: expected"):
        hy.fit(m, x, y, ["k"], jacobian="central")


def test_several_records_with_their_own_preloads() -> None:
    """One k, F_b shared by three records, each with its own preload f0."""
    f0s = [0.3, -0.4, 0.0]
    xs = [
        0.1 + np.sin(np.linspace(0.0, 2 * np.pi * 2, 300)),
        -0.2 + 0.4 * np.sin(np.linspace(0.0, 2 * np.pi * 3, 200)),
        2.0 * np.sin(np.linspace(0.0, 2 * np.pi, 250)),
    ]
    records = []
    for x, f0 in zip(xs, f0s):
        truth = hy.elastoplastic(4.0, 1.5, f0=f0)
        records.append((x, truth.run(x)))
    result = hy.fit_records(hy.elastoplastic(2.0, 0.8), records, ["k", "f_b"], own=["f0"])
    assert result.converged, result.message
    assert result.values["k"] == pytest.approx(4.0, rel=1e-8)
    assert result.values["f_b"] == pytest.approx(1.5, rel=1e-8)
    for i, f0 in enumerate(f0s):
        assert result.values[f"f0[record {i}]"] == pytest.approx(f0, abs=1e-8)
    assert [r["samples"] for r in result.records] == [300, 200, 250]
    assert all(r["rms"] < 1e-8 for r in result.records)
    # the fitted model keeps the starting preload
    assert result.model.params["f0"] == 0.0
    with pytest.raises(hy.FitError, match="record 1: input has 200 samples, output 199"):
        hy.fit_records(hy.elastoplastic(2.0, 0.8), [records[0], (xs[1], records[1][1][:-1])], ["k"])
    with pytest.raises(hy.FitError, match="skips 300 of its 300 samples"):
        hy.fit_records(hy.elastoplastic(2.0, 0.8), records[:1], ["k"], skip=300)
    with pytest.raises(hy.FitError, match="output sample 5 is not finite"):
        bad = records[1][1].copy()
        bad[5] = np.nan
        hy.fit_records(hy.elastoplastic(2.0, 0.8), [(xs[1], bad)], ["k"])


def test_the_budget_bounds_the_work() -> None:
    truth = hy.bouc_wen(0.3, 1.0, 0.8, 0.4, 1.5, stiffness={"z": [0.0], "s": [3.0]})
    x = _record()
    y = truth.run(x)
    start = truth.with_params(w=0.4, beta=0.6, gamma=0.5)
    result = hy.fit(start, x, y, ["w", "beta", "gamma"], max_evaluations=10)
    assert result.status == "not_converged" and "max_evaluations" in result.message
    assert result.evaluations <= 10 + 2 * 3 + 1
    with pytest.raises(hy.FitError, match="max_seconds"):
        hy.fit(start, x, y, ["w"], max_seconds=-1.0)
