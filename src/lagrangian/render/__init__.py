"""The render layer (see DESIGN.md)."""
