"""Alternating frequency-time (AFT) schemes: Fourier coefficients of a
relative displacement in, those of the periodic contact force and its
Jacobian out (:mod:`.schemes`: sampled march and Jenkins with located
events; :mod:`.masing`; :mod:`.dahl`; :mod:`.contact2d`)."""
