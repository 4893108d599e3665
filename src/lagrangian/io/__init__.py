"""The io layer: model files in YAML, TOML or JSON become a :class:`~lagrangian.model.System`.

>>> from lagrangian.io import loads
>>> loads("coordinates: [x]\\nkinetic: x_dot**2/2\\n").coordinates
(x,)

``schema()`` is the JSON Schema (draft 2020-12) of the format; ``SCHEMA_PATH`` is its file.
"""

from lagrangian.io.load import load, loads
from lagrangian.io.model_schema import SCHEMA_PATH, schema

__all__ = ["SCHEMA_PATH", "load", "loads", "schema"]
