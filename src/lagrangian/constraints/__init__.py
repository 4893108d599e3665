"""The constraints layer (see DESIGN.md)."""
