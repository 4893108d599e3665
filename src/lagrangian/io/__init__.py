"""The io layer (see DESIGN.md)."""
