"""Running a batch of records over a Dask cluster.

``map_records(client, model, records)`` sends the model (pickled through
its spec) and the records to the cluster's workers in chunks, runs each
chunk there with ``run_batch`` on one thread per task, and gathers the
outputs in order. The scheduler is Dask's; nothing here schedules::

    from dask.distributed import Client, LocalCluster
    import hysteron_rs as hy
    from hysteron_rs.dask import map_records

    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
        outputs = map_records(client, hy.paper_model(), records)

On a real cluster only the client changes: ``Client("tcp://scheduler:8786")``.
Each record runs from the model's initial state, as in ``run_batch``.
"""

from __future__ import annotations

from typing import Any, List, Optional, Sequence

import numpy as np
import numpy.typing as npt

from ._native import Model, run_batch

__all__ = ["map_records"]


def _run_chunk(model: Model, chunk: Sequence[npt.NDArray[np.float64]]) -> List[npt.NDArray[np.float64]]:
    # One thread per task: Dask runs as many tasks as the workers have threads.
    return run_batch(model, chunk, threads=1)


def map_records(
    client: Any,
    model: Model,
    records: Sequence[npt.ArrayLike],
    *,
    chunk_size: Optional[int] = None,
) -> List[npt.NDArray[np.float64]]:
    """Runs ``model`` over every record on the cluster of ``client``.

    Records are cut into chunks of ``chunk_size`` (default: about four
    chunks per worker thread), each a task; the model is scattered once.
    Errors are raised as in ``run_batch``, naming the record within its
    chunk.
    """
    arrays = [np.ascontiguousarray(r, dtype=np.float64) for r in records]
    if not arrays:
        return []
    if chunk_size is None:
        threads = sum(client.nthreads().values()) or 1
        chunk_size = max(1, len(arrays) // (4 * threads))
    if chunk_size < 1:
        raise ValueError("chunk_size: must be at least 1")
    chunks = [arrays[i : i + chunk_size] for i in range(0, len(arrays), chunk_size)]
    shared = client.scatter(model, broadcast=True)
    futures = client.map(_run_chunk, [shared] * len(chunks), chunks, pure=False)
    out: List[npt.NDArray[np.float64]] = []
    for part in client.gather(futures):
        out.extend(part)
    return out
