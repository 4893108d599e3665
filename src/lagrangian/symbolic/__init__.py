"""The symbolic tools below the model: the safe expression parser, the one door from text and
objects to SymPy, the numerical probe of symbolic questions (is this zero, what is this rank),
the almost-everywhere derivatives of Abs, sign and Heaviside, the naming of coordinates and
their velocities, read-only mappings, and the caches of pure functions with their registry
(docs/architecture.md).  Nothing here knows what a System is.
"""
