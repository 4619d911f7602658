"""The contact-model choice criterion (Chatelet et al. 2008; docs/criterion.md): read a
family of FRFs tagged with excitation force and normal load and say whether a
macroslip or a microslip contact model fits, with or without roughness.

>>> import hbmfric as hf
>>> family = hf.criterion.read_frfs("frfs.csv")  # doctest: +SKIP
>>> result = hf.criterion.choose_contact_model(family)  # doctest: +SKIP
>>> result.model, result.roughness, result.indicators  # doctest: +SKIP

``result.model`` is "macroslip" or "microslip" only when every test lies
clear of its threshold by its margin in noise units
(``result.indicators["margin"]``), and "undecided" when the family lacks
something a step needs or an indicator sits inside the noise
(``result.indicators["undecided_reason"]``: "data" or "noise").
"""

from .choose import CriterionResult, choose_contact_model
from .records import FRFRecord, read_frfs, write_frfs

__all__ = [
    "CriterionResult",
    "FRFRecord",
    "choose_contact_model",
    "read_frfs",
    "write_frfs",
]
