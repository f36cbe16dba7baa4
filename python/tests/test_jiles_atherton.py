"""The Jiles-Atherton model against SciPy's integrator, an implementation
no one here wrote: `scipy.integrate.solve_ivp` (Radau, rtol 1e-10)
integrates the same equations in the field H, one sample's segment at a
time, with the magnetization and its irreversible part as the state;
hysteron integrates them by its own adaptive Dormand-Prince, side by side
of the switch of delta_M."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import hysteron_rs as hy

PARAMS = {"ms": 1.0, "a": 0.3, "k": 0.5, "c": 0.2, "alpha": 0.1}


def langevin(u):
    """L(u) = coth u - 1/u and L'(u), by their series near 0."""
    if abs(u) < 1e-3:
        return u / 3 - u**3 / 45, 1 / 3 - u**2 / 15
    return 1 / np.tanh(u) - 1 / u, 1 / u**2 - 1 / np.sinh(u) ** 2


def scipy_ja(h, ms, a, k, c, alpha):
    """M at each sample of the field h (sample i reached from sample i - 1
    along a straight segment; the path starts at H = 0, demagnetized)."""
    path = np.concatenate([[0.0], h])
    y = np.zeros(2)  # M, M_irr
    out = np.empty(len(h))
    for i in range(len(h)):
        h0, h1 = path[i], path[i + 1]
        if h1 == h0:
            out[i] = y[0]
            continue
        d = 1.0 if h1 > h0 else -1.0

        def flow(hh, yy, d=d):
            m, m_irr = yy
            l, dl = langevin((hh + alpha * m) / a)
            m_an, chi_an = ms * l, ms / a * dl
            lag = m_an - m_irr
            irr = lag / (d * k) if d * lag > 0 else 0.0
            dm_e = c * chi_an + (1 - c) * irr
            den = 1 - alpha * dm_e
            return [dm_e / den, irr / den]

        sol = solve_ivp(flow, (h0, h1), y, method="Radau", rtol=1e-10, atol=1e-13 * ms)
        assert sol.success, sol.message
        y = sol.y[:, -1]
        out[i] = y[0]
    return out


def inner_loops(n):
    t = np.linspace(0.0, 1.0, n)
    return np.sin(4 * np.pi * t) * 2.5 + 0.3 * np.sin(50 * np.pi * t)


@pytest.mark.parametrize(
    "h",
    [
        3.0 * np.sin(np.linspace(0.0, 4 * np.pi, 200)),
        inner_loops(300),
        np.cumsum(np.random.default_rng(5).normal(0.0, 0.25, 200)),
    ],
    ids=["major loop", "minor loops", "random walk"],
)
def test_jiles_atherton_matches_scipys_radau(h):
    ours = np.asarray(hy.jiles_atherton(**PARAMS).run(h))
    theirs = scipy_ja(h, **PARAMS)
    assert np.abs(ours - theirs).max() < 1e-8 * PARAMS["ms"]


def test_a_coupling_that_makes_the_slope_infinite_names_alpha():
    with pytest.raises(hy.ParameterError, match="alpha"):
        hy.jiles_atherton(**{**PARAMS, "alpha": 20.0})
    strong = hy.jiles_atherton(**{**PARAMS, "alpha": 1.5})
    with pytest.raises(hy.HysteronError, match="alpha"):
        strong.run(inner_loops(400))
