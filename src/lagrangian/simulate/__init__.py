"""The simulate layer (see DESIGN.md)."""
