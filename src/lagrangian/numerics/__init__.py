"""The numerics layer (see DESIGN.md)."""
