"""sensitivity: derivatives of the output by forward-mode automatic differentiation."""

from __future__ import annotations

import numpy as np
import pytest

import hysteron_rs as hy


def _cascade() -> hy.Model:
    # y = k·play_r(x), r = 0.5, k = 2: on the rising branch y = k (x − r).
    return hy.Model.from_spec(
        {"type": "cascade", "first": {"type": "play", "r": 0.5}, "second": {"type": "gain", "k": 2.0}}
    )


def test_cascade_matches_the_closed_form() -> None:
    y, dydp = hy.sensitivity(_cascade(), [1.0, 2.0], ["first.play.r", "second.gain.k"])
    assert y.dtype == np.float64 and y.shape == (2,)
    assert dydp.dtype == np.float64 and dydp.shape == (2, 2)
    assert list(y) == [1.0, 3.0]
    assert list(dydp[:, 0]) == [-2.0, -2.0]  # ∂y/∂r = −k
    assert list(dydp[:, 1]) == [0.5, 1.5]  # ∂y/∂k = x − r


def test_suffixes_order_and_initial_state() -> None:
    model = _cascade()
    model.run([5.0])  # the running state does not matter: from the initial state
    y, dydp = hy.sensitivity(model, np.array([1.0, 2.0]), ["k", "r"])
    assert list(y) == [1.0, 3.0]
    assert dydp.tolist() == [[0.5, -2.0], [1.5, -2.0]]


def test_matches_central_differences_on_the_paper_model() -> None:
    model = hy.paper_model()
    x = 1.2 * np.sin(2 * np.pi * np.arange(200) / 100)
    names = model.param_names[:10]  # more than one pass of 8
    y, dydp = hy.sensitivity(model, x, names)
    assert np.allclose(y, model.run(x), rtol=0, atol=1e-9 * np.abs(y).max())
    assert dydp.shape == (200, 10)
    f_c = next(i for i, n in enumerate(names) if n.endswith(".f_c"))
    h = 1e-5
    value = model.params[names[f_c]]
    plus = model.with_params({names[f_c]: value + h}).run(x)
    minus = model.with_params({names[f_c]: value - h}).run(x)
    central = (plus - minus) / (2 * h)
    scale = np.abs(dydp[:, f_c]).max()
    assert scale > 0.1
    assert np.abs(dydp[:, f_c] - central).max() <= 1e-6 * scale


def test_bad_parameter_names_are_parameter_errors() -> None:
    with pytest.raises(hy.ParameterError) as err:
        hy.sensitivity(_cascade(), [1.0, 2.0], ["second.gain.k", "no_such"])
    message = str(err.value)
    assert "`no_such`" in message and "first.play.r" in message
    with pytest.raises(hy.ParameterError, match="given twice"):
        hy.sensitivity(_cascade(), [1.0], ["k", "second.gain.k"])
    with pytest.raises(hy.ParameterError, match="no parameter given"):
        hy.sensitivity(_cascade(), [1.0], [])


def test_bad_inputs_are_input_errors() -> None:
    with pytest.raises(hy.InputError, match="x: is empty"):
        hy.sensitivity(_cascade(), [], ["k"])
    with pytest.raises(hy.InputError) as err:
        hy.sensitivity(_cascade(), [0.0, 1.0, np.nan], ["k"])
    assert "at sample 2" in str(err.value) and err.value.sample == 2
    with pytest.raises(hy.InputError, match="must be 1-D"):
        hy.sensitivity(_cascade(), np.zeros((2, 2)), ["k"])
