"""Same-problem identification bench: ``hysteron_rs.fit`` against scipy.

The problem is the one of the scipy peer in the workplace's
``shared/bench/scipy_fit.py``, run in the same process, interleaved:

* data: 20 000 samples of the numba Bouc-Wen peer (``numba_peers.bw_eul``,
  explicit Euler in input increments) driven by
  ``x_i = 3 exp(-3 i/N) sin(2 pi 10 i/N)``, true
  ``(k, alpha, beta, gamma, n) = (2, 0.1, 0.7, 0.3, 1.5)``, ``A = 1``, plus
  Gaussian noise of 1 % of RMS(H), ``numpy.random.default_rng(12345)``;
* start: the truth times ``(1.3, 1.5, 0.7, 1.4, 0.8)``; free: all five;
* tolerance: MINPACK's ``ftol = xtol = gtol = 1e-8`` on both sides
  (scipy's defaults for ``method="lm"``);
* scipy: ``least_squares(method="lm")`` on the numba model (MINPACK
  ``lmdif``, forward differences), exactly as the peer calls it;
* hysteron: ``fit`` of a ``bouc_wen`` spec with constant stiffness
  (``S = k``, ``w = alpha``, ``alpha = A = 1``), exact Jacobians (the
  default) and central finite differences (``jacobian="fd"``).

The two sides fit different discretisations of one law: scipy the Euler
model that made the data (the "inverse crime"), hysteron the exact flow
(tabulated, ``rtol = 1e-10``), so the fitted values differ by the Euler
model's error; both are printed with the RMS residual (noise: 0.0110).
Wall times are medians over ``--reps`` interleaved repetitions, each fit
whole: ``hysteron_rs.fit``'s time includes the standard errors it reports
at the end (one more Jacobian, unless the search ended where it took its
last), scipy's does not compute them; hysteron's
finite-difference columns run on two threads (its default), scipy on one.
``OPENBLAS_NUM_THREADS`` is 1 unless set.

Run from the repository root, in an environment with numpy, scipy, numba
and the package (``pip install numpy scipy numba ./python``)::

    python python/bench/fit_vs_scipy.py [--peers ../shared/bench] [--reps 7]

``--peers`` is the folder holding ``numba_peers.py`` (the workplace's
``shared/bench``; not part of this repository).
"""

from __future__ import annotations

import os

# numpy's OpenBLAS threads keep spinning after a call and would take the
# second core that hysteron's parallel Jacobian columns use; scipy's lm
# (MINPACK) does not use them. Set before numpy is imported.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import importlib  # noqa: E402
import pathlib  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from typing import Any, Callable, Dict, List, Tuple  # noqa: E402

import numpy as np  # noqa: E402
import numpy.typing as npt  # noqa: E402

import hysteron_rs as hy  # noqa: E402

N = 20_000
NAMES = ["k", "alpha", "beta", "gamma", "n"]
TRUE = np.array([2.0, 0.1, 0.7, 0.3, 1.5])
PERTURB = np.array([1.3, 1.5, 0.7, 1.4, 0.8])
TOL = 1e-8
SEED = 12345
# hysteron's names for (k, alpha, beta, gamma, n) of the peer.
FREE = ["stiffness.s[0]", "w", "beta", "gamma", "n"]

Array = npt.NDArray[np.float64]


def cpu() -> str:
    """The CPU's model name, family/model and AVX-512 flag (Linux)."""
    try:
        info = pathlib.Path("/proc/cpuinfo").read_text()
    except OSError:
        return platform.processor() or "unknown CPU"

    def field(key: str) -> str:
        for line in info.splitlines():
            if line.split(":")[0].strip() == key:
                return line.split(":", 1)[1].strip()
        return "?"

    avx = "AVX-512" if "avx512f" in info else "AVX2, no AVX-512"
    return f"{field('model name')}, family {field('cpu family')}, model {field('model')}, {avx}"


def peer_model(peers: pathlib.Path) -> Callable[[Array, Array], Array]:
    """The numba Euler Bouc-Wen of the peers, as ``model(theta, x)``."""
    sys.path.insert(0, str(peers))
    try:
        numba_peers: Any = importlib.import_module("numba_peers")
    except ImportError as e:
        raise SystemExit(
            f"cannot import numba_peers from {peers} ({e}); pass --peers "
            "with the folder of the workplace's shared/bench"
        ) from e
    bw = numba_peers.compile_kernels(False)["bw_eul"]

    def model(theta: Array, x: Array) -> Array:
        k, alpha, beta, gamma, n = theta
        out = np.empty(x.size)
        bw(x, 1.0, beta, gamma, n, alpha, k, out)
        return out

    return model


def hysteron_start(theta: Array) -> hy.Model:
    k, alpha, beta, gamma, n = (float(v) for v in theta)
    return hy.bouc_wen(alpha, 1.0, beta, gamma, n, 0.0, 0.0, stiffness={"z": [0.0], "s": [k]})


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    root = pathlib.Path(__file__).resolve().parents[2]
    ap.add_argument("--peers", type=pathlib.Path, default=root.parent / "shared" / "bench")
    ap.add_argument("--reps", type=int, default=7)
    a = ap.parse_args()
    least_squares: Any = importlib.import_module("scipy.optimize").least_squares
    scipy_version = importlib.import_module("scipy").__version__
    model = peer_model(a.peers)

    i = np.arange(N)
    x = 3.0 * np.exp(-3.0 * i / N) * np.sin(2 * np.pi * 10 * i / N)
    h_true = model(TRUE, x)  # also compiles the kernel
    rng = np.random.default_rng(SEED)
    sigma = 0.01 * float(np.sqrt(np.mean(h_true**2)))
    y = h_true + sigma * rng.standard_normal(N)
    theta0 = TRUE * PERTURB
    start = hysteron_start(theta0)

    print(f"cpu: {cpu()}")
    print(f"scipy {scipy_version}, numpy {np.__version__}, python {sys.version.split()[0]}")
    print(f"N = {N}, noise sigma = {sigma:.4g}; start " + " ".join(f"{k}={v:.4g}" for k, v in zip(NAMES, theta0)))

    def t_run(f: Callable[[], object], reps: int = 50) -> float:
        t0 = time.perf_counter()
        for _ in range(reps):
            f()
        return (time.perf_counter() - t0) / reps

    truth = hysteron_start(TRUE)
    print(
        f"one simulation: numba Euler {t_run(lambda: model(TRUE, x)) / N * 1e9:.1f} ns/sample, "
        f"hysteron bouc_wen {t_run(lambda: truth.run(x)) / N * 1e9:.1f} ns/sample"
    )

    count = [0]

    def resid(th: Array) -> Array:
        count[0] += 1
        r = model(th, x) - y
        if not np.all(np.isfinite(r)):
            r = np.where(np.isfinite(r), r, 1e6)
        return r

    def scipy_fit() -> Tuple[Array, float, int]:
        count[0] = 0
        res = least_squares(resid, theta0, method="lm", ftol=TOL, xtol=TOL, gtol=TOL)
        return np.asarray(res.x), float(np.sqrt(np.mean(res.fun**2))), count[0]

    def hysteron_fit(jacobian: str) -> Callable[[], Tuple[Array, float, int]]:
        def run() -> Tuple[Array, float, int]:
            r = hy.fit(start, x, y, FREE, ftol=TOL, xtol=TOL, gtol=TOL, jacobian=jacobian)
            if not r.converged:
                raise SystemExit(f"hysteron fit ({jacobian}) did not converge: {r.message}")
            return np.array([r.values[k] for k in FREE]), r.rms, r.evaluations

        return run

    sides: Dict[str, Callable[[], Tuple[Array, float, int]]] = {
        "scipy lm + numba": scipy_fit,
        "hysteron, exact Jacobian": hysteron_fit("exact"),
        "hysteron, finite differences": hysteron_fit("fd"),
    }
    times: Dict[str, List[float]] = {k: [] for k in sides}
    last: Dict[str, Tuple[Array, float, int]] = {}
    for _ in range(a.reps):
        for name, f in sides.items():
            t0 = time.perf_counter()
            last[name] = f()
            times[name].append(time.perf_counter() - t0)

    base = statistics.median(times["scipy lm + numba"])
    print()
    print("| fit | wall median s | min..max | evaluations | RMS residual | speed vs scipy |")
    print("|---|---|---|---|---|---|")
    for name, ts in times.items():
        med = statistics.median(ts)
        _, rms, evals = last[name]
        print(f"| {name} | {med:.4f} | {min(ts):.4f}..{max(ts):.4f} | {evals} | {rms:.6g} | {base / med:.2f}x |")
    print()
    for name, (theta, _, _) in last.items():
        rel = (theta - TRUE) / TRUE
        print(f"{name:30s} " + " ".join(f"{k}={v:.6g} ({e:+.1e})" for k, v, e in zip(NAMES, theta, rel)))


if __name__ == "__main__":
    main()
