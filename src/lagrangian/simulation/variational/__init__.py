"""Variational integrators: the discrete Euler–Lagrange equations of the midpoint rule
(``midpoint``) and of the symplectic Gauss–Legendre / Lobatto IIIA–IIIB collocation methods
(``collocation``), their marches in NumPy and compiled by numba, and the discrete action of
Hamilton's principle (``action``).
"""
