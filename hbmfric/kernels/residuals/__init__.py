"""Harmonic-balance residuals and Jacobians: the full system (:mod:`.hbm`),
the system condensed onto its contact coordinates (:mod:`.condensed`) and the
one entry point the Newton kernels call (:mod:`.dispatch`)."""
