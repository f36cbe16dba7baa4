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
  a summary sent back;
* ``sweep``: 10^4 parameter sets (``--sets``) of the paper model (six of its gap,
  friction and spring parameters spread by up to ±20 %) over 2000 samples of the kernel
  input through ``hysteron_rs.dask.sweep`` on a LocalCluster of 2 worker
  processes against 1 (one thread each), the outputs gathered to the
  client, and the processor time the client (with the scheduler) and the
  workers took per sweep.

``--only`` runs some of them (``--only sweep,dask``).
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
    ap.add_argument("--only", default="run,step,threads,dask,sweep")
    ap.add_argument("--sets", type=int, default=10_000, help="parameter sets of the sweep")
    args = ap.parse_args()
    n, runs = args.samples, args.runs
    only = set(args.only.split(","))
    x = kernel_input(n)
    sections(x, n, runs, only)
    if "sweep" in only:
        sweep_section(x, args.sets, runs)


# The paper model's parameters that the sweep spreads (the others keep
# their values: the stiffness grid must stay increasing, n at least 1).
SPREAD = ["limits.b", "left.mms.f_c", "left.mms.k", "right.bouc_wen.w", "right.bouc_wen.beta", "right.bouc_wen.gamma"]


def sweep_section(x: np.ndarray, sets: int, runs: int) -> None:
    from dask.distributed import Client, LocalCluster

    from hysteron_rs.dask import sweep

    model = hy.paper_model()
    names = list(model.params)
    length = 2000
    rows = np.tile(np.array(list(model.params.values())), (sets, 1))
    spread = np.random.default_rng(7).uniform(0.8, 1.2, (sets, len(SPREAD)))
    for j, name in enumerate(SPREAD):
        rows[:, names.index(name)] *= spread[:, j]
    xs = x[:length]
    want = hy.Ensemble(model, rows).run(xs, errors="nan")
    took: dict = {}
    cpu: dict = {}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
            got = sweep(client, model, rows[:64], xs, errors="nan")  # warm the workers
            got = sweep(client, model, rows, xs, errors="nan")
            assert np.array_equal(got, want, equal_nan=True), "the sweep differs from the local ensemble"
            # and the processor time of the timed sweeps, per sweep: this
            # process (the client and, in a LocalCluster, the scheduler) and
            # the workers
            before, here = client.run(processor_seconds), processor_seconds()
            took[workers] = median_time(lambda: sweep(client, model, rows, xs, errors="nan"), runs)
            after = client.run(processor_seconds)
            cpu[workers] = ((processor_seconds() - here) / runs, sum(after[w] - before[w] for w in after) / runs)
    print(f"sweep   {sets} parameter sets x {length} samples (paper model): 1 worker {took[1]:.3f} s, 2 workers {took[2]:.3f} s, speed-up {took[1] / took[2]:.2f}x")
    for workers in (1, 2):
        print(f"sweep   processor time per sweep on {workers} worker(s): client and scheduler {cpu[workers][0]:.2f} s, workers {cpu[workers][1]:.2f} s ({os.cpu_count()} processors)")


def processor_seconds() -> float:
    """User and system time of this process so far (all its threads)."""
    t = os.times()
    return t.user + t.system


def sections(x: np.ndarray, n: int, runs: int, only: set) -> None:
    model = hy.paper_model()
    if "run" in only:
        run_section(model, x, n, runs)
    if "step" in only:
        step_section(runs)
    if "threads" in only:
        threads_section(x, n, runs)
    if "dask" in only:
        dask_section(model, x, n, runs)


def run_section(model: "hy.Model", x: np.ndarray, n: int, runs: int) -> None:
    rust = rust_paper_ns(n, runs)

    def run_once() -> None:
        model.reset()
        model.run(x)

    py = median_time(run_once, runs) / n * 1e9
    print(f"run     paper model, {n} samples: Python {py:.2f} ns/sample, hysteron bench {rust:.2f} ns/sample, ratio {py / rust:.3f}")


def step_section(runs: int) -> None:
    gain = hy.gain(1.0)
    calls = 1_000_000
    step = gain.step
    values = [0.1] * calls

    def steps() -> None:
        for v in values:
            step(v)

    per_call = median_time(steps, runs) / calls * 1e6
    print(f"step    {per_call:.3f} µs per call (gain, {calls} calls)")


def threads_section(x: np.ndarray, n: int, runs: int) -> None:
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


def dask_section(model: "hy.Model", x: np.ndarray, n: int, runs: int) -> None:
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
