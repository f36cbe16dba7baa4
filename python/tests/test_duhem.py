"""The semilinear Duhem model against SciPy's integrator, an implementation
no one here wrote: `scipy.integrate.solve_ivp` (DOP853, rtol 1e-12)
integrates `dy/dt = α |ẋ| (a x − y) + b ẋ` in time along the same
piecewise-linear input, one segment at a time; hysteron solves each
sample's travel in closed form."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import hysteron_rs as hy

PARAMS = {"alpha": 2.0, "a": 1.0, "b": 0.2, "y0": 0.3}


def scipy_duhem(x, alpha, a, b, y0):
    """The output at each sample of the input x, sample i at time i, x
    linear in between, from y0 at x = 0 (the path starts with a segment
    from 0 to x[0])."""
    path = np.concatenate([[0.0], x])
    y = y0
    out = np.empty(len(x))
    for i in range(len(x)):
        x_from, rate = path[i], path[i + 1] - path[i]

        def flow(t, yy):
            xt = x_from + rate * t
            return [alpha * abs(rate) * (a * xt - yy[0]) + b * rate]

        sol = solve_ivp(flow, (0.0, 1.0), [y], method="DOP853", rtol=1e-12, atol=1e-14)
        y = sol.y[0, -1]
        out[i] = y
    return out


@pytest.mark.parametrize(
    "x",
    [
        3.0 * np.sin(np.linspace(0.0, 6 * np.pi, 300)),
        np.cumsum(np.random.default_rng(3).normal(0.0, 0.2, 300)),
        np.sin(np.linspace(0.0, 4 * np.pi, 300)) + 0.2 * np.sin(np.linspace(0.0, 60 * np.pi, 300)),
    ],
    ids=["cycles", "random walk", "inner loops"],
)
def test_duhem_matches_scipys_integration(x):
    ours = np.asarray(hy.duhem(**PARAMS).run(x))
    theirs = scipy_duhem(x, **PARAMS)
    assert np.abs(ours - theirs).max() < 1e-9 * np.abs(theirs).max()


def test_a_cycle_converges_to_the_closed_form_branches():
    # after many cycles of amplitude A the branches are the steady loop:
    # increasing from −A, y = a x + (b − a)/α + C e^{−α (x + A)}
    p = PARAMS
    amplitude = 2.0
    t = np.linspace(0.0, 20 * np.pi, 20001)
    x = amplitude * np.sin(t)
    y = np.asarray(hy.duhem(**p).run(x))
    last = slice(len(t) - 1000, len(t))  # the last half cycle but one
    xs, ys = x[last], y[last]
    rising = np.diff(xs, prepend=xs[0]) > 0
    u_inf = (p["b"] - p["a"]) / p["alpha"]
    # on the steady rising branch, u = y − a x relaxes from its value at −A
    u = ys[rising] - p["a"] * xs[rising]
    s = xs[rising] + amplitude
    # the steady loop: u(−A) = u0 with u0 = −u_inf (1 − E)/(1 + E), E = e^{−2αA}
    e = np.exp(-2 * p["alpha"] * amplitude)
    u0 = -u_inf * (1 - e) / (1 + e)
    want = u_inf + (u0 - u_inf) * np.exp(-p["alpha"] * s)
    assert np.abs(u - want).max() < 1e-9
