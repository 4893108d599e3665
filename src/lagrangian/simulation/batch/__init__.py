"""Batches: many initial states or parameter sets of one system in one call (``run``:
``simulate_batch``), integrated as members of one engine — the C loop, the vectorized NumPy
loop or, with constraints, the multiplier form member by member — into one ``Batch``
(``result``).
"""
