"""The modules of :mod:`lagrangian.compiled`, compiled at install (empty where nothing was)."""
