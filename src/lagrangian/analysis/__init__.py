"""The analysis layer (see DESIGN.md)."""
