"""A family of FRFs by a parameter study, written as CSV and read back by
the contact-model criterion (the paper's choice of contact model)."""

import hbmfric as hf
from hbmfric.criterion import choose_contact_model, read_frfs


def build(p):
    law = hf.Jenkins(
        stiffness=3.0e4, friction_coefficient=1.0, normal_load=p["normal_load"]
    )
    return hf.Oscillator(1.0, 4.0, 1.0e4, law)


if __name__ == "__main__":
    ratios = (10.0, 0.5, 0.2, 0.1, 0.001)  # Fex/Fn, the paper's Fig. 8
    params = [
        {"force": r * fn, "normal_load": fn} for r in ratios for fn in (1.0, 10.0)
    ]
    result = hf.study(build, params, (50.0, 300.0))
    result.to_csv("family.csv")
    verdict = choose_contact_model(read_frfs("family.csv"))
    print(verdict)
