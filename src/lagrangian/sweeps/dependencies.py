"""The packages a sweep needs beyond lagrangian's own: Dask (distributed), xarray, Zarr and
cryptography (the local cluster's TLS credentials, which distributed does not require).

They are imported only when a sweep runs, so ``import lagrangian`` stays fast; missing ones
are named with the command that installs them.
"""

from __future__ import annotations

import importlib.util

from lagrangian.errors import SimulationError

INSTALL_HINT = "pip install lagrangian[sweep]"
#: Import name -> what pip calls it.
PACKAGES = {
    "dask": "dask",
    "distributed": "distributed",
    "xarray": "xarray",
    "zarr": "zarr",
    "cryptography": "cryptography",
}


def missing_packages() -> list[str]:
    """The packages of a sweep that cannot be imported (without importing them)."""
    return [pip for name, pip in PACKAGES.items() if importlib.util.find_spec(name) is None]


def require_sweep_packages() -> None:
    """Raise SimulationError, with the install command, when a package of a sweep is missing."""
    missing = missing_packages()
    if missing:
        raise SimulationError(
            f"A sweep needs {', '.join(missing)}, which {'is' if len(missing) == 1 else 'are'} "
            f"not installed: {INSTALL_HINT}"
        )
