"""The one project-wide JIT decorator.

Every kernel is compiled with ``cache=True`` (the compiled code is stored next
to the source and reused by later processes), ``nogil=True`` and
``error_model="numpy"`` (division by zero gives inf/nan instead of raising,
so that kernels stay exception-free and report problems by status codes).
"""

from numba import njit

jit = njit(cache=True, nogil=True, error_model="numpy")

__all__ = ["jit"]
