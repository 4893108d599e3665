"""The numerics layer (see docs/architecture.md)."""
