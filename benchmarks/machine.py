"""What every benchmark report says about the machine: the CPU and the versions measured."""

from __future__ import annotations

import importlib.metadata
import platform
from pathlib import Path


def package_version(package: str) -> str:
    """The installed version of ``package``, or "not installed"."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def cpu_model() -> str:
    """The CPU's model name (from /proc/cpuinfo where there is one)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def compiled_forms() -> str:
    """How lagrangian's compiled modules run here (``lagrangian.compiled``): "all 8 compiled",
    "Python (not compiled)", or which are."""
    try:
        from lagrangian.compiled import modules
    except ImportError:
        return "unknown (lagrangian not importable)"
    forms = modules()
    done = [name for name, form in forms.items() if form == "compiled"]
    if len(done) == len(forms):
        return f"all {len(forms)} compiled"
    if not done:
        return "Python (not compiled)"
    return f"{len(done)} of {len(forms)} compiled: {', '.join(done)}"
