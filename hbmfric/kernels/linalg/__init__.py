"""Dense linear algebra with status codes: LU (:mod:`.lu`) and the linear
first-harmonic response (:mod:`.linear_response`)."""
