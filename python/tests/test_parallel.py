"""Threads, batches and the Dask path give the serial results."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import hysteron_rs as hy


def _records(n: int, length: int) -> list:
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 1.0, length)
    return [a * np.sin(2 * np.pi * f * t) for a, f in zip(rng.uniform(0.5, 2.0, n), rng.uniform(1, 5, n))]


def test_two_threads_two_models_match_serial_runs() -> None:
    x = _records(1, 200_000)[0]
    want = hy.paper_model().run(x)
    models = [hy.paper_model(), hy.paper_model()]
    out: dict = {}

    def work(i: int) -> None:
        out[i] = models[i].run(x)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert np.array_equal(out[0], want) and np.array_equal(out[1], want)


def test_one_model_in_two_threads_is_refused_not_corrupted() -> None:
    model = hy.paper_model()
    x = _records(1, 2_000_000)[0]
    errors: list = []
    results: list = []

    def work() -> None:
        try:
            results.append(model.run(x))
        except RuntimeError as e:  # PyO3's borrow check: "Already borrowed"
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) + len(errors) == 2 and results


def test_run_batch_and_parameter_sets_match_serial_runs() -> None:
    model = hy.paper_model()
    records = _records(16, 3000)
    for threads in (None, 1, 2):
        got = hy.run_batch(model, records, threads=threads)
        for r, y in zip(records, got):
            fresh = hy.paper_model()
            assert np.array_equal(y, fresh.run(r))
    x = records[0]
    sets = [{"left.mms.f_c": f} for f in (0.5, 1.0, 2.0)]
    got = hy.run_parameter_sets(model, sets, x)
    for s, y in zip(sets, got):
        assert np.array_equal(y, model.with_params(s).run(x))


def _peak(y: np.ndarray) -> float:
    return float(np.max(np.abs(y)))


def test_dask_local_cluster_with_two_workers(tmp_path) -> None:
    distributed = pytest.importorskip("dask.distributed")
    from hysteron_rs.dask import map_records

    model = hy.paper_model()
    records = _records(12, 2000)
    paths = []
    for i, r in enumerate(records):
        paths.append(str(tmp_path / f"record{i}.npy"))
        np.save(paths[-1], r)
    bad = [r.copy() for r in records]
    bad[9][5] = np.nan
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            assert len(client.nthreads()) == 2
            got = map_records(client, model, records)
            loaded = map_records(client, model, paths, load=np.load, chunk_size=5)
            peaks = map_records(client, model, paths, load=np.load, reduce=_peak)
            with pytest.raises(hy.InputError) as err:
                map_records(client, model, bad, chunk_size=4)
            assert map_records(client, model, []) == []
    assert len(got) == len(loaded) == len(peaks) == len(records)
    for r, y, z, p in zip(records, got, loaded, peaks):
        want = hy.paper_model().run(r)
        assert np.array_equal(y, want) and np.array_equal(z, want)
        assert p == _peak(want)
    # Record 9 is record 1 of the third chunk: named by its place in the batch.
    assert err.value.index == 9 and err.value.sample == 5
    assert str(err.value).startswith("record 9: at sample 5")


def test_parameter_set_errors_name_the_set() -> None:
    model = hy.paper_model()
    x = _records(1, 100)[0]
    with pytest.raises(hy.ParameterError, match=r"^set 1: unknown parameter `nope`"):
        hy.run_parameter_sets(model, [{"f_c": 1.0}, {"nope": 1.0}], x)
    with pytest.raises(hy.ParameterError, match=r"^set 0: parameter `f_c`: abc is not a number"):
        hy.run_parameter_sets(model, [{"f_c": "abc"}], x)
    with pytest.raises(hy.ParameterError, match=r"^parameter `f_c`: abc is not a number"):
        model.with_params(f_c="abc")


def test_dask_sweep_is_the_local_ensemble() -> None:
    distributed = pytest.importorskip("dask.distributed")
    from hysteron_rs.dask import sweep

    model = hy.mms(1.0, 20.0)
    rows = np.column_stack(
        [np.linspace(0.5, 1.5, 50), np.linspace(5.0, 60.0, 50), np.zeros(50)]
    )
    x = _records(1, 1500)[0]
    bad = rows.copy()
    bad[37, 0] = -1.0
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        with distributed.Client(cluster) as client:
            got = sweep(client, model, rows, x)
            small = sweep(client, model, rows, x, chunk_size=7)
            with pytest.raises(hy.ParameterError) as err:
                sweep(client, model, bad, x, chunk_size=8)
            # two chunks fail: the one with the first row raises, whichever finishes first
            worse = bad.copy()
            worse[45, 1] = -2.0
            with pytest.raises(hy.ParameterError) as first:
                sweep(client, model, worse, x, chunk_size=8)
            nan = sweep(client, model, bad, x, errors="nan")
            peaks = sweep(client, model, rows, x, chunk_size=7, reduce=_peak)
            nan_peaks = sweep(client, model, bad, x, errors="nan", reduce=_peak)
            with pytest.raises(hy.ParameterError) as reduced_err:
                sweep(client, model, bad, x, chunk_size=8, reduce=_peak)
    want = hy.Ensemble(model, rows).run(x)
    assert np.array_equal(got, want) and np.array_equal(small, want)
    # row 37 is row 5 of the fifth chunk of eight: named by its place in params
    assert err.value.index == 37 and str(err.value).startswith("instance 37: ")
    assert first.value.index == 37
    assert np.isnan(nan[37]).all() and np.array_equal(np.delete(nan, 37, 0), np.delete(want, 37, 0))
    # reduced on the workers: each row's summary, in the rows' order
    assert peaks == [_peak(y) for y in want]
    assert np.isnan(nan_peaks[37]) and nan_peaks[:37] + nan_peaks[38:] == peaks[:37] + peaks[38:]
    assert reduced_err.value.index == 37
