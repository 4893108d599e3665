"""Where a sweep runs: a Dask cluster of local processes, or a running one by its address.

The local cluster listens on the loopback interface only (127.0.0.1), one single-threaded
worker process per core unless ``workers`` says otherwise, each restarted by its nanny when
it dies.  A running cluster is reached at its scheduler's address (``tcp://HOST:PORT``,
started with ``dask scheduler`` and ``dask worker tcp://HOST:PORT``); its workers must have
lagrangian installed.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from lagrangian.errors import Problem, SimulationError, SimulationInputError, raise_if_problems

#: Seconds to wait for a running scheduler to answer.
CONNECT_TIMEOUT = 10


def check_cluster_options(scheduler: str | None, workers: int | None) -> None:
    """Refuse workers that are not a positive count, or given with a scheduler."""
    raise_if_problems(
        cluster_problems(scheduler, workers), "Cannot start the sweep", SimulationInputError
    )


def cluster_problems(scheduler: str | None, workers: int | None) -> list[Problem]:
    """What :func:`check_cluster_options` refuses, as problems (to be raised with others)."""
    problems = []
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
    ):
        problems.append(
            Problem("workers", f"{workers!r} is not a positive whole number", "give workers >= 1")
        )
    if workers is not None and scheduler:
        fix = "leave out workers: a running cluster has its own (start more with dask worker)"
        problems.append(Problem("workers", "applies to the local cluster only", fix))
    return problems


@contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None) -> Iterator[Any]:
    """A dask.distributed Client of the cluster at ``scheduler``, or of a LocalCluster of
    ``workers`` processes (default: one per core) on 127.0.0.1, closed on the way out."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except OSError as error:
            raise SimulationError(
                f"scheduler: cannot reach the Dask scheduler at {scheduler} ({error}); start "
                "one with `dask scheduler` and its workers with `dask worker ADDRESS`"
            ) from None
        with client:
            yield client
        return
    with (
        LocalCluster(
            n_workers=workers or os.cpu_count() or 1,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address="127.0.0.1:0",
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client
