"""Integrators of the state equations dx/dt = f(t, x): the protocol every formulation and
integrator shares (``protocol``), the one Python loop that steps a SciPy ``OdeSolver`` (``loop``),
the fixed-step RK4, events, the step and wall-time budget, the compiled C loop's adapter, and
the piecewise loop that continues a run across a change of its equations (``piecewise``).
"""
