"""Analysis on the constraint manifold of a constrained system: the manifold itself
(``constraint_manifold``), its statics (rest and equilibria), linearization and modes in
independent coordinates, and its symmetries and first integrals.
"""
