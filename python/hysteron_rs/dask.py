"""Running a batch of records, or an ensemble of parameter sets, over a
Dask cluster.

``map_records(client, model, records)`` sends the model (pickled through
its spec) to every worker once, cuts the records into chunks, runs each
chunk on a worker with ``run_batch`` on one thread per task, and gathers
the results in order. The scheduler is Dask's; nothing here schedules::

    from dask.distributed import Client, LocalCluster
    import hysteron_rs as hy
    from hysteron_rs.dask import map_records

    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
        outputs = map_records(client, hy.paper_model(), records)

On a real cluster only the client changes: ``Client("tcp://scheduler:8786")``.

Records sent from the client travel through it (8 bytes a sample each
way), which on a small machine costs as much as a fast model's run. Where
the records live on storage the workers can read, send their names and a
``load`` function instead, and reduce each output on the worker when only
a summary is wanted::

    rms = map_records(client, model, paths, load=np.load,
                      reduce=lambda y: float(np.sqrt(np.mean(y * y))))

Each record runs from the model's initial state, as in ``run_batch``.

``sweep(client, model, params, x)`` runs one instance of ``model`` per row
of ``params`` over ``x``, as ``Ensemble(model, params).run(x)`` does, with
the rows cut into chunks that are ensembles of their own on the workers.
Its outputs come back through the client too (8 bytes per instance and
sample); where each instance's output is wanted only as a summary (a
Monte-Carlo study of a peak force or a loop energy), ``reduce`` computes
it on the workers::

    peaks = sweep(client, model, params, x, reduce=lambda y: float(np.abs(y).max()))
"""

from __future__ import annotations

from typing import Any, Callable, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

from ._native import Ensemble, HysteronError, Model, run_batch

__all__ = ["map_records", "sweep"]


def _run_chunk(
    model: Model,
    offset: int,
    chunk: Sequence[Any],
    load: Optional[Callable[[Any], npt.ArrayLike]],
    reduce: Optional[Callable[[npt.NDArray[np.float64]], Any]],
) -> List[Any]:
    arrays = [load(r) for r in chunk] if load is not None else chunk
    try:
        # One thread per task: Dask runs as many tasks as the workers have threads.
        outputs: List[Any] = run_batch(model, arrays, threads=1)
    except HysteronError as e:
        raise _renumbered(e, offset) from None
    return [reduce(y) for y in outputs] if reduce is not None else outputs


def _renumbered(e: HysteronError, offset: int, what: str = "record") -> HysteronError:
    """``e`` (about entry ``i`` of a chunk) about entry ``offset + i``."""
    local = getattr(e, "index", None)
    if local is None:
        return e
    prefix = f"{what} {local}: "
    message = str(e)
    if message.startswith(prefix):
        message = message[len(prefix) :]
    out = type(e)(f"{what} {offset + local}: {message}")
    out.index = offset + local  # type: ignore[attr-defined]
    if hasattr(e, "sample"):
        out.sample = e.sample  # type: ignore[attr-defined]
    return out


def map_records(
    client: Any,
    model: Model,
    records: Sequence[Any],
    *,
    load: Optional[Callable[[Any], npt.ArrayLike]] = None,
    reduce: Optional[Callable[[npt.NDArray[np.float64]], Any]] = None,
    chunk_size: Optional[int] = None,
) -> List[Any]:
    """Runs ``model`` over every record on the cluster of ``client``.

    ``records`` are 1-D float arrays, or, with ``load``, anything ``load``
    turns into one on the worker (file names, keys, seeds). ``reduce``,
    if given, is applied to each output on the worker and its result is
    returned instead of the output. Both must be picklable (module-level
    functions, or what cloudpickle takes).

    Records are cut into chunks of ``chunk_size`` (default: about four
    chunks per worker thread), each a task. An error is raised as in
    ``run_batch``, with ``index`` the record's position in ``records``.
    """
    if load is None:
        items: List[Any] = [np.ascontiguousarray(r, dtype=np.float64) for r in records]
    else:
        items = list(records)
    if not items:
        return []
    if chunk_size is None:
        threads = sum(client.nthreads().values()) or 1
        chunk_size = max(1, len(items) // (4 * threads))
    if chunk_size < 1:
        raise ValueError("chunk_size: must be at least 1")
    offsets = list(range(0, len(items), chunk_size))
    chunks = [items[i : i + chunk_size] for i in offsets]
    shared = client.scatter(model, broadcast=True, hash=False)
    # Scattered, the chunks go to the workers directly, not through the
    # scheduler inside the task graph.
    data = client.scatter(chunks, hash=False)
    n = len(chunks)
    futures = client.map(
        _run_chunk, [shared] * n, offsets, data, [load] * n, [reduce] * n, pure=False
    )
    out: List[Any] = []
    for part in client.gather(futures):
        out.extend(part)
    return out


def _run_ensemble(
    model: Model,
    offset: int,
    rows: npt.NDArray[np.float64],
    x: npt.NDArray[np.float64],
    errors: str,
    reduce: Optional[Callable[[npt.NDArray[np.float64]], Any]],
) -> Any:
    try:
        # One thread per task: Dask runs as many tasks as the workers have threads.
        outputs = Ensemble(model, rows).run(x, errors=errors, threads=1)
    except HysteronError as e:
        raise _renumbered(e, offset, "instance") from None
    return outputs if reduce is None else [reduce(y) for y in outputs]


def sweep(
    client: Any,
    model: Model,
    params: npt.ArrayLike,
    x: npt.ArrayLike,
    *,
    errors: str = "raise",
    chunk_size: Optional[int] = None,
    reduce: Optional[Callable[[npt.NDArray[np.float64]], Any]] = None,
) -> Any:
    """``Ensemble(model, params).run(x, errors=errors)`` on the cluster of
    ``client``: the outputs, shape ``(len(params), len(x))``, each row the
    bits the model gives alone with that row's parameters.

    With ``reduce`` (picklable, as for ``map_records``), the list of
    ``reduce(row)`` for the rows in order instead, each computed on the
    worker that ran the row, so that only the summaries travel (with
    ``errors="nan"`` a refused instance's row of NaN is reduced too).

    The rows are cut into chunks of ``chunk_size`` (default: about four
    chunks per worker thread, in multiples of eight, the lanes of one
    vector block), each an ensemble run as one task, its rows fetched as
    soon as it is done, while the others run. An error is raised as
    ``Ensemble.run`` raises it, with ``index`` the row's position in
    ``params`` (of the failing rows, the first).
    """
    rows = np.ascontiguousarray(params, dtype=np.float64)
    samples = np.ascontiguousarray(x, dtype=np.float64)
    if rows.ndim != 2 or rows.shape[0] == 0:
        # the ensemble's own message for a bad matrix
        Ensemble(model, rows)
    if chunk_size is None:
        threads = sum(client.nthreads().values()) or 1
        per_task = -(-rows.shape[0] // (4 * threads))
        chunk_size = 8 * max(1, -(-per_task // 8))
    if chunk_size < 1:
        raise ValueError("chunk_size: must be at least 1")
    offsets = list(range(0, rows.shape[0], chunk_size))
    shared = client.scatter(model, broadcast=True, hash=False)
    shared_x = client.scatter(samples, broadcast=True, hash=False)
    data = client.scatter([rows[i : i + chunk_size] for i in offsets], hash=False)
    n = len(offsets)
    futures = client.map(
        _run_ensemble,
        [shared] * n,
        offsets,
        data,
        [shared_x] * n,
        [errors] * n,
        [reduce] * n,
        pure=False,
    )
    # Each chunk is fetched as soon as it is done, while the others run,
    # into its rows of the output; a failed chunk raises, the first by
    # row, once every chunk is done.
    from distributed import as_completed

    out: Any = np.empty((rows.shape[0], samples.shape[0])) if reduce is None else [None] * rows.shape[0]
    at = {f.key: i for f, i in zip(futures, offsets)}
    failed: List[Tuple[int, Any]] = []
    for future in as_completed(futures):
        i = at[future.key]
        if future.status == "error":
            failed.append((i, future))
        else:
            part = future.result()
            out[i : i + len(part)] = part
    if failed:
        min(failed, key=lambda f: f[0])[1].result()
    return out
