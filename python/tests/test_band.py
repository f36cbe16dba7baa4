"""FitResult.predict_band: linearized and Monte-Carlo bands, their errors."""

from __future__ import annotations

import numpy as np
import pytest

import hysteron_rs as hy


R, K1, K0 = "left.cascade.first.play.r", "left.cascade.second.gain.k", "right.gain.k"


def _fit(
    noise: float = 0.05, seed: int = 1, free: tuple[str, ...] = (R, K1, K0)
) -> tuple[hy.FitResult, np.ndarray]:
    """`y = k1·play_r(x) + k0·x` fitted to 300 samples with Gaussian noise."""
    t = np.linspace(0.0, 1.0, 300)
    x = 2.0 * np.exp(-t) * np.sin(2 * np.pi * 3 * t + 0.3)
    truth = hy.play(0.4).then(hy.gain(1.5)).plus(hy.gain(0.8))
    y = truth.run(x) + np.random.default_rng(seed).normal(0.0, noise, x.size)
    start = truth.with_params(**{name: 1.2 * truth.params[name] for name in free})
    result = hy.fit(start, x, y, list(free))
    assert result.converged, result.message
    return result, x


def test_linearized_band_is_symmetric_about_the_fitted_output() -> None:
    result, x = _fit()
    band = result.predict_band(x)
    assert (band.level, band.method, band.failed_draws) == (0.95, "linearized", 0)
    assert isinstance(band.output, np.ndarray) and band.output.shape == x.shape
    np.testing.assert_array_equal(band.output, result.model.run(x))
    half = band.upper - band.output
    np.testing.assert_allclose(band.output - band.lower, half, rtol=1e-12, atol=1e-15)
    assert np.all(half > 0.0)
    # a wider level, a wider band
    wide = result.predict_band(x, level=0.99)
    assert np.all(wide.upper - wide.lower > band.upper - band.lower)


def test_monte_carlo_band_agrees_with_the_linearized_one_on_a_linear_model() -> None:
    # the gains free, the threshold held: the output is linear in them
    result, x = _fit(noise=0.01, seed=3, free=(K1, K0))
    lin = result.predict_band(x, method="linearized")
    mc = result.predict_band(x, method="monte_carlo", draws=20000, seed=7)
    assert mc.method == "monte_carlo" and mc.failed_draws == 0
    ratio = (mc.upper - mc.lower) / (lin.upper - lin.lower)
    assert np.max(np.abs(ratio - 1.0)) <= 0.05, np.max(np.abs(ratio - 1.0))
    again = result.predict_band(x, method="monte_carlo", draws=20000, seed=7)
    np.testing.assert_array_equal(mc.lower, again.lower)


def test_bad_requests_raise_typed_errors() -> None:
    result, x = _fit()
    with pytest.raises(hy.HysteronError, match="level"):
        result.predict_band(x, level=1.0)
    with pytest.raises(hy.HysteronError, match="method"):
        result.predict_band(x, method="bootstrap")
    with pytest.raises(hy.HysteronError, match="draws"):
        result.predict_band(x, method="monte_carlo", draws=0)
    with pytest.raises(hy.HysteronError, match="draws"):
        result.predict_band(x, method="monte_carlo", draws=-3)
    with pytest.raises(hy.FitError, match="needs at least 40"):
        result.predict_band(x, method="monte_carlo", draws=10)
    with pytest.raises(hy.InputError):
        result.predict_band(np.array([0.1, np.nan]))
