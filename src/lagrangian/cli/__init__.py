"""The cli layer: the `lagrangian` command (docs/architecture.md)."""
