"""First integrals beyond the cyclic momenta and the energy: the Noether charges of point
symmetries (``noether``, ``lie_symmetries``), integrals quadratic and cubic in the velocities
(``quadratic``), integrals that hold for special parameters (``conditional``) or on the
constraints (``constrained``), sought in a function basis (``function_basis``) by a sampled
null space (``null_vectors``) and checked symbolically (``search``).
"""
