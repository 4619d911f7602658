"""Dynamic Lagrangian frequency-time (DLFT) for the rigid Coulomb contact
(:mod:`.coulomb`) and its located variant with the linear tail (:mod:`.tail`)."""
