"""Discrete Fourier operators (:mod:`.dft`) and Fourier integrals of a force
known over pieces of the period (:mod:`.segments`)."""
