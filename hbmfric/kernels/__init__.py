"""Numba kernels: flat arrays and scalars in, arrays and status codes out."""
