"""Kernels of Hill's stability: the Jacobians of many solutions in one loop and
the signs of determinants of their blocks (:mod:`.hill`)."""
