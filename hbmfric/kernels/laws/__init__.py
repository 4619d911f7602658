"""Contact laws as time-domain updates: the law contract and integer codes
(:mod:`.updates`: Jenkins, Menq, Iwan, roughness, cubic), the modified Dahl
increment (:mod:`.dahl`)."""
