"""One continuation step: the bordered Newton corrector and tangent
(:mod:`.newton`), the step with its acceptance rules (:mod:`.arclength`) and
the truncation-error estimate it watches (:mod:`.truncation`)."""
