"""Speed of the Python face, measured side by side with the Rust figures.

Run from the repository root after installing the package
(``bash scripts/test.sh`` makes target/py-venv):

    target/py-venv/bin/python python/bench/bench.py [--samples N] [--runs R]

Prints, on the same machine in the same run:

* ``run``: ``model.run`` of the paper model on the kernel input of
  ``hysteron bench`` (10^7 samples), next to ``hysteron bench --kernel
  "paper model"`` run just before (median of R runs each; the ratio is the
  Python overhead: argument conversion, the output array);
* ``step``: the cost of one ``model.step(x)`` call on a gain (the call
  overhead, the model's own work being ~1 ns), median of R loops;
* ``threads``: two paper models run in two threads against the same two
  runs one after the other (the GIL is released while a model runs);
* ``dask``: 64 records through ``hysteron_rs.dask.map_records`` on a
  LocalCluster of 2 worker processes against 1 (one thread each), sent
  from the client, and loaded by the workers from ``.npy`` files with only
  a summary sent back.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import statistics
import subprocess
import tempfile
import threading
import time

import numpy as np

import hysteron_rs as hy

ROOT = pathlib.Path(__file__).resolve().parents[2]


def kernel_input(n: int) -> np.ndarray:
    i = np.arange(n, dtype=np.float64)
    return 2.5 * np.sin(2 * np.pi * i / 2000.0) + 0.3 * np.sin(2 * np.pi * i / 97.3)


def median_time(f, runs: int) -> float:
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def rust_paper_ns(samples: int, runs: int) -> float:
    binary = os.environ.get("HYSTERON_BIN", str(ROOT / "target" / "release" / "hysteron"))
    out = subprocess.run(
        [binary, "bench", "--samples", str(samples), "--runs", str(runs), "--kernel", "paper model"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 6 and cells[1] == "paper model":
            return float(cells[4])
    raise RuntimeError(f"no `paper model` row in:\n{out}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=10_000_000)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    n, runs = args.samples, args.runs
    x = kernel_input(n)

    rust = rust_paper_ns(n, runs)
    model = hy.paper_model()

    def run_once() -> None:
        model.reset()
        model.run(x)

    py = median_time(run_once, runs) / n * 1e9
    print(f"run     paper model, {n} samples: Python {py:.2f} ns/sample, hysteron bench {rust:.2f} ns/sample, ratio {py / rust:.3f}")

    gain = hy.gain(1.0)
    calls = 1_000_000
    step = gain.step
    values = [0.1] * calls

    def steps() -> None:
        for v in values:
            step(v)

    per_call = median_time(steps, runs) / calls * 1e6
    print(f"step    {per_call:.3f} µs per call (gain, {calls} calls)")

    xs = x[: n // 2]
    models = [hy.paper_model(), hy.paper_model()]

    def serial() -> None:
        for m in models:
            m.reset()
            m.run(xs)

    def parallel() -> None:
        for m in models:
            m.reset()
        ts = [threading.Thread(target=m.run, args=(xs,)) for m in models]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    t_serial = median_time(serial, runs)
    t_parallel = median_time(parallel, runs)
    print(f"threads two models, {xs.size} samples each: serial {t_serial:.3f} s, two threads {t_parallel:.3f} s, speed-up {t_serial / t_parallel:.2f}x")

    from dask.distributed import Client, LocalCluster

    from hysteron_rs.dask import map_records

    length = max(1, n // 16)  # 625 000 samples each by default: 0.04 s of work each
    records = [x[:length] + 0.01 * i for i in range(64)]
    with tempfile.TemporaryDirectory() as tmp:
        paths = []
        for i, r in enumerate(records):
            paths.append(os.path.join(tmp, f"record{i}.npy"))
            np.save(paths[-1], r)
        sent: dict = {}
        loaded: dict = {}
        for workers in (1, 2):
            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
                map_records(client, model, records[:4])  # warm the workers
                sent[workers] = median_time(lambda: map_records(client, model, records), runs)
                loaded[workers] = median_time(lambda: map_records(client, model, paths, load=np.load, reduce=peak), runs)
    print(f"dask    64 records x {length} samples sent from the client: 1 worker {sent[1]:.3f} s, 2 workers {sent[2]:.3f} s, speed-up {sent[1] / sent[2]:.2f}x")
    print(f"dask    64 records x {length} samples loaded by the workers (np.load, peak |y| back): 1 worker {loaded[1]:.3f} s, 2 workers {loaded[2]:.3f} s, speed-up {loaded[1] / loaded[2]:.2f}x")


def peak(y: np.ndarray) -> float:
    return float(np.max(np.abs(y)))


if __name__ == "__main__":
    main()
