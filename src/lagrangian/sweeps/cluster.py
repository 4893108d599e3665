"""Where a sweep runs: a Dask cluster of local processes, or a running one by its address.

Whoever can connect to a Dask scheduler can have its workers run any function, as the user
who started them.  So the local cluster speaks TLS with credentials made for it alone
(``Security.temporary()``: a certificate authority and a certificate that live in this
process and its workers only), although it listens on the loopback interface only
(127.0.0.1), which every user of the machine can reach.  It has one single-threaded worker
process per core unless ``workers`` says otherwise, each restarted by its nanny when it dies.

A running cluster is reached at its scheduler's address.  One shared with others needs TLS
too: started with ``dask scheduler --tls-ca-file CA --tls-cert CERT --tls-key KEY`` (and its
workers with the same options), it is given as ``tls://HOST:PORT`` with a certificate of
the same authority (:func:`tls_security`), or with Dask's own configuration
(``distributed.comm.tls``).  Its workers must have lagrangian installed.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from lagrangian.errors import (
    Fix,
    Problem,
    Setting,
    SimulationError,
    SimulationInputError,
    raise_if_problems,
)

#: Seconds to wait for a running scheduler to answer.
CONNECT_TIMEOUT = 10


#: Dask's options for the TLS files of its scheduler and workers (``dask scheduler --help``),
#: which ``lagrangian sweep`` takes under the same names, as the client's own.
TLS_OPTIONS = ("--tls-ca-file", "--tls-cert", "--tls-key")


def check_cluster_options(
    scheduler: str | None, workers: int | None, security: Any | None = None
) -> None:
    """Refuse workers that are not a positive count, or given with a scheduler, and TLS
    credentials given without a ``tls://`` scheduler."""
    raise_if_problems(
        cluster_problems(scheduler, workers, security),
        "Cannot start the sweep",
        SimulationInputError,
    )


def cluster_problems(
    scheduler: str | None, workers: int | None, security: Any | None = None
) -> list[Problem]:
    """What :func:`check_cluster_options` refuses, as problems (to be raised with others)."""
    problems = _security_problems(scheduler, "security") if security is not None else []
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
    ):
        problems.append(
            Problem(
                "workers",
                f"{workers!r} is not a positive whole number",
                Fix("give {0.name} >= 1", (Setting("workers"),)),
            )
        )
    if workers is not None and scheduler:
        fix = Fix(
            "leave out {0.name}: a running cluster has its own (start more with dask worker)",
            (Setting("workers"),),
        )
        problems.append(Problem("workers", "applies to the local cluster only", fix))
    return problems


def _security_problems(scheduler: str | None, field: str) -> list[Problem]:
    """Credentials (given as ``field``) without the address of a TLS scheduler."""
    if not scheduler:
        fix = f"leave out {field}: the local cluster makes its own temporary credentials"
        return [Problem(field, "applies to a running cluster only", fix)]
    if not scheduler.startswith("tls://"):
        fix = f"give the scheduler's address as tls://HOST:PORT, not {scheduler}"
        return [Problem("scheduler", "TLS credentials need a tls:// address", fix)]
    return []


def tls_security(
    scheduler: str | None,
    ca_file: str | None = None,
    cert: str | None = None,
    key: str | None = None,
) -> Any | None:
    """Dask's Security for a client of a scheduler started with
    ``dask scheduler --tls-ca-file CA --tls-cert CERT --tls-key KEY``: the scheduler is
    checked against the authority ``ca_file``, and the client shows ``cert`` (its key in
    ``key``, or in the same file), which that authority signed; ``scheduler`` must be a
    ``tls://`` address.  None when no file is given.  Problems name Dask's options
    (:data:`TLS_OPTIONS`), as ``lagrangian sweep`` takes them."""
    files = dict(zip(TLS_OPTIONS, (ca_file, cert, key)))
    if not any(files.values()):
        return None
    problems = [
        Problem(option, f"cannot read {path}", "give the path of a PEM file")
        for option, path in files.items()
        if path and not os.access(path, os.R_OK)
    ]
    for option in TLS_OPTIONS[:2]:
        if not files[option]:
            fix = f"give {option} as well (the key may be in the file of --tls-cert)"
            problems.append(Problem(option, "missing", fix))
    problems += _security_problems(scheduler, "/".join(TLS_OPTIONS))
    raise_if_problems(problems, "Bad TLS options", SimulationInputError)
    from distributed.security import Security

    return Security(
        tls_ca_file=ca_file, tls_client_cert=cert, tls_client_key=key, require_encryption=True
    )


@contextmanager
def dask_client(
    scheduler: str | None = None, workers: int | None = None, security: Any | None = None
) -> Iterator[Any]:
    """A dask.distributed Client of the cluster at ``scheduler`` (with ``security``, else
    Dask's configuration), or of a LocalCluster of ``workers`` processes (default: one per
    core) on 127.0.0.1 that speaks TLS with temporary credentials, closed on the way out."""
    from dask.distributed import Client, LocalCluster
    from distributed.security import Security

    if scheduler:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT, security=security)
        except OSError as error:
            raise SimulationError(
                f"scheduler: cannot reach the Dask scheduler at {scheduler} ({error}); start "
                "one with `dask scheduler` and its workers with `dask worker ADDRESS`"
            ) from None
        with client:
            yield client
        return
    credentials = Security.temporary()  # needs the cryptography package
    with (
        LocalCluster(
            n_workers=workers or os.cpu_count() or 1,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            protocol="tls://",
            security=credentials,
            dashboard_address="127.0.0.1:0",
        ) as cluster,
        Client(cluster, security=credentials) as client,
    ):
        yield client
