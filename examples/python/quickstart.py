"""hysteron_rs quickstart: compose a model, fit it to a record, plot the loops.

A transmission-like model is composed from the algebra: a friction slider
(Modified Maxwell-slip, ``mms``) that moves inside a backlash gap, in
mechanical series with a Bouc-Wen-like spring. A "measured" record is made
by running the model with known parameters on a decaying sine and adding
1 % noise; the friction level, its stiffness and the spring's hysteresis
parameters are then fitted from a deliberately wrong start, and the
measured and fitted force-displacement loops are plotted.

Run from the repository root after ``pip install "./python[examples]"``
(the ``examples`` extra brings matplotlib, which the plot needs)::

    python examples/python/quickstart.py [--output quickstart.png]
"""

from __future__ import annotations

import argparse
from typing import List, Optional, Tuple

import numpy as np

import hysteron_rs as hy


def compose(f_c: float, k: float, w: float, beta: float) -> hy.Model:
    """Friction in a 0.3-wide gap, in series with a stiffening spring."""
    friction = hy.mms(f_c=f_c, k=k)
    spring = hy.bouc_wen(
        w=w,
        alpha=1.0,
        beta=beta,
        gamma=1.0,
        n=1.0,
        stiffness={"z": [0.0, 0.6, 1.2], "s": [8.0, 10.0, 16.0]},
    )
    return friction.series(spring, limits={"type": "gap", "b": 0.3, "r0": 0.0})


def main(argv: Optional[List[str]] = None) -> Tuple[hy.Model, hy.FitResult]:
    """Runs the quickstart; returns the true model and the fit result."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", default="quickstart.png", help="the PNG to write")
    args = ap.parse_args(argv)

    # The "measured" record: 4 cycles of a decaying sine, 1 % noise.
    t = np.linspace(0.0, 4.0, 8000)
    x = 1.4 * np.exp(-0.25 * t) * np.sin(2.0 * np.pi * t)
    truth = compose(f_c=2.0, k=40.0, w=0.4, beta=3.0)
    clean = truth.run(x)
    rng = np.random.default_rng(7)
    measured = clean + 0.01 * np.std(clean) * rng.standard_normal(x.size)

    # Fit from a start off by 25-50 %.
    start = compose(f_c=1.5, k=25.0, w=0.6, beta=2.0)
    result = hy.fit(start, x, measured, ["f_c", "k", "w", "beta"])
    print(result)
    for name, value in result.values.items():
        interval = result.ci95[name]  # None where JᵀJ is singular
        ci = f"95 % [{interval[0]:.4f}, {interval[1]:.4f}]" if interval else "no interval"
        print(f"{name:28s} true {truth.params[name]:8.4f}  fitted {value:8.4f}  {ci}")

    fitted = result.model.run(x)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (loops, time) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    loops.plot(x, measured, lw=3.0, color="0.75", label="measured")
    loops.plot(x, start.run(x), lw=1.0, color="tab:orange", ls="--", label="start")
    loops.plot(x, fitted, lw=1.2, color="tab:blue", label="fitted")
    loops.set_xlabel("displacement x")
    loops.set_ylabel("force F")
    loops.set_title("force-displacement loops")
    loops.legend(loc="upper left")
    time.plot(t, measured - fitted, lw=0.6, color="tab:blue")
    time.set_xlabel("time t")
    time.set_ylabel("measured − fitted")
    time.set_title(f"residual (RMS {result.rms:.3g}, NRMSE {result.nrmse:.2g})")
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output}")
    return truth, result


if __name__ == "__main__":
    main()
