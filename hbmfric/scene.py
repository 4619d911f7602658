"""Runs described in files: ``hbmfric run scene.toml``.

A scene file (TOML) names a system, its contact, the FRF to trace, what to
write, and optionally a study grid (one FRF per combination). Every table
and key is checked: an unknown key or a bad value is refused with its path
in the file (``scene.toml: [contact] stiffness: ...``). Example::

    [system]
    kind = "oscillator"          # oscillator | beam | tensioner | matrices
    mass = 1.0                   # kg
    damping = 0.02               # N s/m
    stiffness = 1.0              # N/m

    [contact]
    law = "jenkins"              # jenkins | menq | iwan | coulomb | dahl | cubic
    stiffness = 3.0              # | roughness | none; the law's own arguments
                                 # (contact2d: a [[contacts]] entry with normal)
    slip_force = 1.0

    [frf]
    force = 0.5                  # N
    omega = [0.5, 3.0]           # rad/s (or frequency_hz = [lo, hi])
    harmonics = "auto"           # or an integer; any hf.frf keyword

    [output]
    directory = "results"        # relative to the scene file
    csv = "frf.csv"
    png = "frf.png"              # omit for no plot (no matplotlib import)
    npz = "frf.npz"
    dof = 0                      # DOF of the CSV and plot (default: contact)

    [study]                      # optional: one FRF per combination
    "frf.force" = [0.1, 0.5, 2.0]
    "contact.normal_load" = [1.0, 10.0]   # (laws given by μ and N)
    executor = "processes"       # or "serial"

A study axis is ``"frf.force"`` or a path into ``[system]``, ``[contact]``
or ``[[contacts]]``: ``"contact.normal_load"``, ``"system.load.0"`` (the
load of DOF 0), ``"contact.base.friction_coefficient"`` (a roughness
law's base), ``"contacts.0.slip_force"`` or ``"contacts[1].stiffness"``
(entries counted from 0 in the order of the file).

For ``kind = "matrices"``, several contacts, or a contact between two
DOFs, are an array of tables instead of ``[contact]``::

    [[contacts]]
    law = "jenkins"
    stiffness = 2000.0
    slip_force = 1.0
    dof = 1                      # index or name
    other = 2                    # omit for a contact to ground

The paper's scenes ship as examples in ``examples/scenes/``.
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
import math
import tomllib
from pathlib import Path

SYSTEM_KINDS = ("oscillator", "beam", "tensioner", "matrices")
LAWS = (
    "jenkins",
    "menq",
    "iwan",
    "coulomb",
    "dahl",
    "cubic",
    "roughness",
    "contact2d",
    "none",
)
TOP_LEVEL = ("system", "contact", "contacts", "frf", "output", "study")
OUTPUT_KEYS = ("directory", "csv", "png", "npz", "dof")
#: keys of a ``[[contacts]]`` entry besides the law and its arguments
PLACEMENT_KEYS = ("dof", "other", "normal", "normal_other")
STUDY_OPTIONS = ("executor", "workers", "normal_load", "sets")


class SceneError(ValueError):
    """A scene file that cannot be run; the message names the file and the
    key path."""


def _fail(where: str, msg: str) -> SceneError:
    return SceneError(f"{where}: {msg}")


def _unknown(keys, accepted) -> str:
    """``'omga' (did you mean 'omega'?), ...`` for unknown keys."""
    import difflib

    out = []
    for key in keys:
        close = difflib.get_close_matches(str(key), [str(a) for a in accepted], n=1)
        out.append(f"{key!r} (did you mean {close[0]!r}?)" if close else repr(key))
    return ", ".join(out)


def _unknown_tables(names) -> str:
    """``[outptu] (did you mean [output]?), ...`` for unknown tables."""
    import difflib

    out = []
    for name in names:
        close = difflib.get_close_matches(str(name), TOP_LEVEL, n=1)
        out.append(f"[{name}]" + (f" (did you mean [{close[0]}]?)" if close else ""))
    return ", ".join(out)


def _law_class(name: str):
    import hbmfric as hf

    return {
        "jenkins": hf.Jenkins,
        "menq": hf.Menq,
        "iwan": hf.Iwan,
        "coulomb": hf.Coulomb,
        "dahl": hf.ModifiedDahl,
        "cubic": hf.Cubic,
        "roughness": hf.Roughness,
        "contact2d": hf.Contact2D,
    }[name]


def _call(where: str, cls, kwargs: dict, extra: dict | None = None):
    """``cls(**kwargs, **extra)`` with unknown keys of ``kwargs`` (the
    file's) and bad values reported at ``where``; ``extra`` are arguments
    the scene supplies itself (the contact law)."""
    extra = extra or {}
    params = inspect.signature(cls).parameters
    accepted = [p for p in params if p not in extra and p != "self"]
    unknown = sorted(set(kwargs) - set(accepted))
    if unknown:
        raise _fail(
            where,
            f"unknown key(s) {_unknown(unknown, accepted)} (accepted: "
            f"{', '.join(accepted)})",
        )
    try:
        return cls(**kwargs, **extra)
    except (TypeError, ValueError) as exc:
        raise _fail(where, str(exc)) from None


def _tuple_values(d: dict, keys) -> dict:
    return {
        k: tuple(v) if k in keys and isinstance(v, list) else v for k, v in d.items()
    }


def build_contact(table: dict | None, where: str, normal: bool = False):
    """The contact law of a ``[contact]`` table (None for ``law = "none"``
    or no table); ``normal``: the entry names a normal DOF, which the 2D
    element (``law = "contact2d"``) needs."""
    if table is None:
        return None
    if not isinstance(table, dict):
        raise _fail(where, "must be a table")
    t = dict(table)
    law = t.pop("law", None)
    if law is None:
        raise _fail(where, f"missing key 'law' (one of {', '.join(LAWS)})")
    if law not in LAWS:
        raise _fail(f"{where} law", f"unknown law {law!r} (one of {', '.join(LAWS)})")
    if law == "none":
        if t:
            raise _fail(where, f"law 'none' takes no other keys, got {sorted(t)}")
        return None
    cls = _law_class(law)
    if law == "contact2d" and not normal:
        raise _fail(
            f"{where} law",
            "the 2D element acts on a tangential and a normal DOF: give it as a "
            "[[contacts]] entry of a kind = 'matrices' scene, with dof "
            "(tangential) and normal, and hold its preload by a [system] "
            "static_load on the normal DOF",
        )
    if law == "roughness":
        base = t.pop("base", None)
        if not isinstance(base, dict):
            raise _fail(where, "law 'roughness' needs a [contact.base] table (the law)")
        base_law = build_contact(base, f"{where[:-1]}.base]")
        return _call(where, cls, t, {"law": base_law})
    if law == "menq" and t.pop("from_stiffness", False):
        return _call(where, cls.from_stiffness, t)
    if law == "iwan":
        t = _tuple_values(t, ("stiffnesses", "slip_forces", "friction_coefficients"))
    if law == "dahl":
        t = _tuple_values(t, ("upper", "lower"))
    return _call(where, cls, t)


def build_contacts(entries, where: str) -> list:
    """The contacts of a ``[[contacts]]`` array of tables: each entry is a
    law's table (as ``[contact]``) plus where it acts, ``dof`` (index or
    name, required), ``other`` (the DOF on the other side of the joint;
    omit for a contact to ground), ``normal`` and ``normal_other``."""
    import hbmfric as hf

    if not isinstance(entries, list) or not entries:
        raise _fail(where, "must be a non-empty array of tables ([[contacts]])")
    contacts = []
    for i, entry in enumerate(entries):
        here = f"{where}[{i}]"
        if not isinstance(entry, dict):
            raise _fail(here, "must be a table")
        t = dict(entry)
        place = {k: t.pop(k) for k in PLACEMENT_KEYS if k in t}
        if "dof" not in place:
            raise _fail(here, "missing key 'dof' (the DOF the law acts on)")
        if t.get("law") == "none":
            raise _fail(f"{here} law", "a [[contacts]] entry needs a contact law")
        law = build_contact(t, here, normal="normal" in place)
        dof = place.pop("dof")
        try:
            contacts.append(hf.Contact(law, dof, **place))
        except (TypeError, ValueError) as exc:
            raise _fail(here, str(exc)) from None
    return contacts


def build_system(scene: dict, name: str):
    """The system of a parsed scene (see the module notes)."""
    import hbmfric as hf

    where = f"{name}: [system]"
    table = scene.get("system")
    if not isinstance(table, dict):
        raise _fail(name, "missing table [system]")
    t = dict(table)
    kind = t.pop("kind", None)
    if kind not in SYSTEM_KINDS:
        raise _fail(
            f"{name}: [system] kind",
            f"must be one of {', '.join(SYSTEM_KINDS)}, got {kind!r}",
        )
    contact = build_contact(scene.get("contact"), f"{name}: [contact]")
    contacts = None
    if "contacts" in scene:
        if kind != "matrices":
            raise _fail(
                f"{name}: [[contacts]]",
                f"only kind 'matrices' takes several contacts; kind {kind!r} has "
                "its contact in [contact]",
            )
        if scene.get("contact") is not None:
            raise _fail(name, "give [contact] or [[contacts]], not both")
        for key in ("contact_dof", "contacts"):
            if key in t:
                raise _fail(
                    f"{where} {key}",
                    "with [[contacts]], each contact says where it acts (dof, other)",
                )
        contacts = build_contacts(scene["contacts"], f"{name}: [[contacts]]")
    if kind == "oscillator":
        if "damping_ratio" in t:
            if "damping" in t:
                raise _fail(where, "give damping or damping_ratio, not both")
            zeta = t.pop("damping_ratio")
            try:
                t["damping"] = (
                    2.0
                    * float(zeta)
                    * math.sqrt(float(t["stiffness"]) * float(t["mass"]))
                )
            except (KeyError, TypeError, ValueError):
                raise _fail(
                    where, "damping_ratio needs numeric mass and stiffness"
                ) from None
        return _call(where, hf.Oscillator, t, {"contact": contact})
    if kind == "beam":
        return _call(where, hf.CantileverBeam, t, {"contact": contact})
    if kind == "tensioner":
        if contact is not None and not isinstance(contact, hf.ModifiedDahl):
            raise _fail(f"{name}: [contact]", "the tensioner takes law = 'dahl'")
        extra = {"tensioner": contact} if contact is not None else {}
        return _call(where, hf.BeltTensioner, t, extra)
    # matrices
    base = Path(scene.get("_directory", "."))
    files = {}
    for key in ("mass", "stiffness", "damping"):
        if key in t:
            value = t.pop(key)
            if isinstance(value, str):
                head, sep, var = value.rpartition(":")
                path = (
                    head if sep and head.lower().endswith((".mat", ".npz")) else value
                )
                var = var if sep and path == head else None
                try:
                    files[key] = hf.read_matrix(base / path, var)
                except (OSError, ValueError) as exc:
                    msg = str(exc)
                    if "name=" in msg:
                        msg = msg.replace(
                            "say which with name=",
                            f'say which in the scene: {key} = "{path}:<name>"',
                        )
                    raise _fail(f"{where} {key}", msg) from None
            else:
                files[key] = value
    if "mass" not in files or "stiffness" not in files:
        raise _fail(where, "kind 'matrices' needs mass and stiffness (file names)")
    if "load" in t and isinstance(t["load"], dict):
        t["load"] = {
            (int(k) if k.isdigit() else k): _complex(v) for k, v in t["load"].items()
        }
    if "static_load" in t and isinstance(t["static_load"], dict):
        # TOML keys are strings: `{ 80 = 5.0 }` is DOF 80, as for `load`
        # (it was refused as an unknown DOF name '80')
        t["static_load"] = {
            (int(k) if k.isdigit() else k): v for k, v in t["static_load"].items()
        }
    if "rayleigh" in t and isinstance(t["rayleigh"], list):
        t["rayleigh"] = tuple(t["rayleigh"])
    if contacts is not None:
        return _call(where, hf.LinearStructure, {**files, **t}, {"contacts": contacts})
    return _call(where, hf.LinearStructure, {**files, **t}, {"contact": contact})


def _complex(v):
    """A load value: a number, or ``[re, im]``."""
    if isinstance(v, list) and len(v) == 2:
        return complex(v[0], v[1])
    return v


def _frf_options(scene: dict, name: str) -> tuple[float, tuple[float, float], dict]:
    import hbmfric as hf

    where = f"{name}: [frf]"
    t = dict(scene.get("frf") or {})
    accepted = set(inspect.signature(hf.frf).parameters) - {
        "system",
        "force",
        "omega",
        "option_overrides",
        "options",
    }
    accepted |= {f.name for f in dataclasses.fields(hf.ContinuationOptions)}
    unknown = sorted(set(t) - accepted - {"force", "omega", "frequency_hz"})
    if unknown:
        raise _fail(
            where,
            f"unknown key(s) "
            f"{_unknown(unknown, ['force', 'omega', 'frequency_hz', *accepted])} "
            f"(accepted: force, omega, frequency_hz, {', '.join(sorted(accepted))})",
        )
    if "force" not in t:
        raise _fail(where, "missing key 'force' (N)")
    force = t.pop("force")
    if isinstance(force, bool) or not isinstance(force, int | float):
        raise _fail(
            f"{where} force",
            f"must be a number, the forcing amplitude in N (no units in the "
            f"value), got {force!r}",
        )
    if "omega" in t and "frequency_hz" in t:
        raise _fail(where, "give omega (rad/s) or frequency_hz, not both")
    if "frequency_hz" in t:
        band = t.pop("frequency_hz")
        scale = 2.0 * math.pi
    elif "omega" in t:
        band = t.pop("omega")
        scale = 1.0
    else:
        raise _fail(where, "missing key 'omega' (rad/s, [low, high]) or frequency_hz")
    if not (isinstance(band, list) and len(band) == 2):
        raise _fail(f"{where} omega", f"must be [low, high], got {band!r}")
    try:
        omega = (float(band[0]) * scale, float(band[1]) * scale)
    except (TypeError, ValueError):
        raise _fail(f"{where} omega", f"must be two numbers, got {band!r}") from None
    return force, omega, t


@dataclasses.dataclass
class Scene:
    """A checked scene.

    Attributes
    ----------
    name : str
        The file (for messages).
    data : dict
        The parsed TOML.
    directory : Path
        The scene file's directory (relative paths start there).
    """

    name: str
    data: dict
    directory: Path

    def system(self, overrides: dict | None = None):
        """The system, with ``{"contact.normal_load": 3.0, ...}`` applied."""
        return build_system(self._with(overrides), self.name)

    def _with(self, overrides: dict | None) -> dict:
        d = copy.deepcopy(self.data)
        d["_directory"] = str(self.directory)
        for path, value in (overrides or {}).items():
            parts = split_path(path)
            if parts[0] == "contacts":
                target = self._contact_entry(d, path, parts)
                parts = parts[2:]
            else:
                target = d.setdefault(parts[0], {})
                parts = parts[1:]
            where = f"{self.name}: [study] {path!r}"
            # keys of a table are text ("system.load.0": the load of DOF 0)
            for part in parts[:-1]:
                target = target.setdefault(str(part), {})
                if not isinstance(target, dict):
                    raise _fail(where, f"{str(part)!r} is not a table")
            target[str(parts[-1])] = value
        return d

    def _contact_entry(self, d: dict, path: str, parts: list) -> dict:
        """The ``[[contacts]]`` entry a study path ``contacts.<i>.<key>``
        names, or a :class:`SceneError` naming the path."""
        where = f"{self.name}: [study] {path!r}"
        entries = d.get("contacts")
        if not isinstance(entries, list) or not entries:
            hint = ""
            if len(parts) >= 3:
                hint = f" (did you mean 'contact.{'.'.join(map(str, parts[2:]))}'?)"
            raise _fail(where, f"the scene has no [[contacts]]{hint}")
        n = len(entries)
        span = "index 0" if n == 1 else f"indices 0 to {n - 1}"
        if len(parts) < 3 or not isinstance(parts[1], int):
            raise _fail(
                where,
                "a path into [[contacts]] is 'contacts.<index>.<key>' or "
                f"'contacts[<index>].<key>' (the scene has {n} [[contacts]], {span})",
            )
        index = parts[1]
        if not 0 <= index < n:
            raise _fail(
                where,
                f"no [[contacts]] entry {index}: the scene has {n} ({span}, in the "
                "order of the file)",
            )
        entry = entries[index]
        if not isinstance(entry, dict):
            raise _fail(f"{self.name}: [[contacts]][{index}]", "must be a table")
        return entry

    def frf_call(self, overrides: dict | None = None):
        """``(force, omega, keyword arguments)`` of :func:`hbmfric.frf`."""
        return _frf_options(self._with(overrides), self.name)


def load_scene(path: str | Path) -> Scene:
    """Read and check a scene file.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    SceneError
        (a ``ValueError``) for a TOML syntax error, an unknown table or key,
        or a bad value; the message names the file and the key path.
    """
    path = Path(path)
    name = str(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise _fail(name, f"not valid TOML: {exc}") from None
    unknown = sorted(set(data) - set(TOP_LEVEL))
    if unknown:
        raise _fail(
            name,
            f"unknown table(s) {_unknown_tables(unknown)} (accepted: "
            f"{', '.join(f'[{t}]' for t in TOP_LEVEL)})",
        )
    out = data.get("output", {})
    bad = sorted(set(out) - set(OUTPUT_KEYS))
    if bad:
        raise _fail(
            f"{name}: [output]",
            f"unknown key(s) {', '.join(map(repr, bad))} (accepted: "
            f"{', '.join(OUTPUT_KEYS)})",
        )
    scene = Scene(name, data, path.resolve().parent)
    system = scene.system()  # checks [system] and [contact]
    _check_system(scene, system)
    if "dof" in out:
        from .results import _resolve_dof

        dof = out["dof"]
        if isinstance(dof, bool) or not isinstance(dof, int | str):
            raise _fail(
                f"{name}: [output] dof", f"must be a DOF index or name, got {dof!r}"
            )
        try:
            _resolve_dof(dof, getattr(system, "dof_names", None) or {}, system.n_dof)
        except (TypeError, ValueError) as exc:
            raise _fail(f"{name}: [output] dof", str(exc)) from None
    _check_frf(name, scene.frf_call())  # checks [frf]
    sets = study_sets(scene)
    for key in {key: None for p in sets for key in p}:
        _check_axis(scene, key)
    for p in sets[:1]:
        _check_system(scene, scene.system(p))
        _check_frf(name, scene.frf_call(p))
    _check_set_values(scene, sets)
    _check_output_dof(scene, system, sets)
    return scene


def _check_set_values(scene: Scene, sets: list[dict]) -> None:
    """The values of every study set after the first (which is checked
    whole), at load time: per set, its ``frf.force``, its values in
    ``[contact]`` / ``[[contacts]]`` together (the laws and their placement
    built, no model) and its ``system.*`` values together for the built-in
    kinds (a cheap build); ``system.*`` values of kind ``"matrices"`` are
    left to the run (a build reads the matrix files). Each distinct group
    of values is checked once; a bad one is a :class:`SceneError` naming
    the set (counted from 0), its keys and values, and the message of the
    table it lands in."""
    name = scene.name
    kind = (scene.data.get("system") or {}).get("kind")
    seen: set = set()
    for i, p in enumerate(sets[1:], start=1):
        groups: dict[str, dict] = {}
        for key, value in p.items():
            table = "frf" if key == "frf.force" else split_path(key)[0]
            table = "contact" if table == "contacts" else table
            groups.setdefault(table, {})[key] = value
        for table, values in groups.items():
            sig = (table, repr(sorted(values.items(), key=lambda kv: kv[0])))
            if sig in seen or (table == "system" and kind == "matrices"):
                continue
            seen.add(sig)
            try:
                if table == "frf":
                    _check_frf(name, scene.frf_call(values))
                elif table == "contact":
                    d = scene._with(values)
                    if d.get("contacts") is not None:
                        build_contacts(d["contacts"], f"{name}: [[contacts]]")
                    else:
                        build_contact(d.get("contact"), f"{name}: [contact]")
                elif table == "system":
                    _check_system(scene, scene.system(values))
            except SceneError as exc:
                msg = str(exc)
                inner = msg[len(name) + 2 :] if msg.startswith(f"{name}: ") else msg
                said = ", ".join(f"{k!r} = {v!r}" for k, v in values.items())
                raise _fail(f"{name}: [study] set {i} ({said})", inner) from None


def _check_output_dof(scene: Scene, system, sets: list[dict]) -> None:
    """An ``[output] dof`` index must mean one DOF in every model of the
    study: refused, before anything runs, when a ``system.*`` axis changes
    the DOF count (a beam's ``n_elements``), as
    :meth:`hbmfric.study.StudyResult.table` would refuse it after the
    runs."""
    dof = scene.data.get("output", {}).get("dof")
    if not isinstance(dof, int) or isinstance(dof, bool):
        return
    if not any(key.startswith("system.") for p in sets for key in p):
        return
    counts = {int(system.n_dof)}
    for p in sets:
        counts.add(int(scene.system(p).n_dof))
    if len(counts) > 1:
        raise _fail(
            f"{scene.name}: [output] dof",
            f"{dof} is a DOF index, but the study's models have "
            f"{', '.join(map(str, sorted(counts)))} DOFs (a [study] axis in "
            "[system] changes the model): the index is a different point in "
            "each; name the DOF (such as 'tip') or leave dof unset for each "
            "model's contact DOF",
        )


def _check_system(scene: Scene, system) -> None:
    """The checks :func:`hbmfric.frf` makes on entry (contacts together,
    DOF ranges, matrices), at load time with the table's path."""
    from .systems.protocol import check_system

    try:
        check_system(system)
    except (TypeError, ValueError) as exc:
        table = "[[contacts]]" if "contacts" in scene.data else "[system]"
        raise _fail(f"{scene.name}: {table}", str(exc)) from None


def _check_frf(name: str, call) -> None:
    """The values of ``[frf]`` that need no system: ``force``, ``omega``,
    the continuation options, ``harmonics``, ``sweep``,
    ``harmonic_tolerance``, ``retrace`` (the others are checked by the
    run)."""
    import hbmfric as hf

    from ._validate import finite_float
    from .api import _omega_range

    force, omega, kwargs = call
    where = f"{name}: [frf]"
    fields = {f.name for f in dataclasses.fields(hf.ContinuationOptions)}
    options = {k: v for k, v in kwargs.items() if k in fields}
    try:
        finite_float("force", force)
        _omega_range(omega)
        hf.ContinuationOptions(**options)
        h = kwargs.get("harmonics", "auto")
        if h != "auto" and (isinstance(h, bool) or not isinstance(h, int) or h < 1):
            raise ValueError(
                f"harmonics must be a positive integer or 'auto', got {h!r}"
            )
        if kwargs.get("sweep", "up") not in ("up", "down"):
            raise ValueError(f"sweep must be 'up' or 'down', got {kwargs['sweep']!r}")
        if "harmonic_tolerance" in kwargs:
            finite_float(
                "harmonic_tolerance",
                kwargs["harmonic_tolerance"],
                low=0.0,
                low_open=True,
                high=1.0,
            )
        if not isinstance(kwargs.get("retrace", True), bool):
            raise TypeError(f"retrace must be true or false, got {kwargs['retrace']!r}")
    except (TypeError, ValueError) as exc:
        raise _fail(where, str(exc)) from None


def split_path(path: str) -> list:
    """The parts of a study path: ``"contact.normal_load"`` ->
    ``["contact", "normal_load"]``, ``"contacts.1.stiffness"`` and
    ``"contacts[1].stiffness"`` -> ``["contacts", 1, "stiffness"]``
    (an index an int, a malformed bracket left as text for the check to
    refuse)."""
    parts: list = []
    for piece in str(path).split("."):
        head, bracket, rest = piece.partition("[")
        if bracket and rest.endswith("]") and rest[:-1].strip().isdigit():
            if head:
                parts.append(head)
            parts.append(int(rest[:-1]))
        elif piece.isdigit():
            parts.append(int(piece))
        else:
            parts.append(piece)
    return parts


def _flatten(prefix: str, value, out: dict) -> None:
    """Unquoted dotted keys arrive as nested tables; their leaves (a list or
    a value) get the dotted path."""
    if isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}" if prefix else str(k), v, out)
    else:
        out[prefix] = value


def _check_axis(scene: Scene, key: str) -> None:
    """A study axis names ``frf.force`` or a path into ``[system]``,
    ``[contact]`` or ``[[contacts]]``."""
    name = scene.name
    parts = split_path(key)
    table = parts[0]
    if key == "frf.force" or (table in ("system", "contact") and len(parts) >= 2):
        if table == "contact" and scene.data.get("contacts") is not None:
            rest = ".".join(map(str, parts[1:]))
            raise _fail(
                f"{name}: [study] {key!r}",
                f"the scene's contacts are in [[contacts]]: say which one, such as "
                f"'contacts.0.{rest}'",
            )
        return
    if table == "contacts":
        scene._contact_entry(scene.data, key, parts)
        return
    raise _fail(
        f"{name}: [study] {key!r}",
        "study axes are 'frf.force' or paths into [system], [contact] or "
        "[[contacts]], such as 'contact.normal_load' or 'contacts.0.slip_force'",
    )


def study_sets(scene: Scene) -> list[dict]:
    """The parameter sets of the ``[study]`` table (empty without one): the
    grid of its axes, or its explicit ``sets``."""
    import hbmfric as hf

    raw = dict(scene.data.get("study") or {})
    if not raw:
        return []
    sets = raw.pop("sets", None)
    for k in ("executor", "workers", "normal_load"):
        raw.pop(k, None)
    t = {}
    for k, v in raw.items():  # unquoted dotted keys arrive as nested tables
        _flatten(k, v, t)
    where = f"{scene.name}: [study]"
    if sets is not None:
        if t:
            raise _fail(where, "give grid axes or sets, not both")
        if not isinstance(sets, list) or not all(isinstance(s, dict) for s in sets):
            raise _fail(f"{where} sets", "must be an array of tables")
        flat = []
        for s in sets:
            f: dict = {}
            _flatten("", s, f)
            flat.append(f)
        return flat
    for k, v in t.items():
        if not isinstance(v, list) or not v:
            raise _fail(
                f"{where} {k!r}", f"a grid axis must be a non-empty list, got {v!r}"
            )
    return hf.grid(**t)


class SceneBuilder:
    """``build(parameters)`` for :func:`hbmfric.study`: the scene's system
    with the parameter set's overrides (picklable)."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene

    def __call__(self, params: dict):
        return self.scene.system({k: v for k, v in params.items() if k != "frf.force"})


def run_scene(path: str | Path, out: str | Path | None = None, progress=print) -> dict:
    """Run a scene file: trace its FRF (or its study) and write the outputs.

    Parameters
    ----------
    path : str or Path
        The scene file.
    out : str or Path, optional
        Output directory, overriding ``[output] directory``.
    progress : callable
        Receives one line per step (``print`` by default).

    Returns
    -------
    dict
        ``"branch"`` (or ``"study"``), ``"written"`` (paths).
    """
    import hbmfric as hf

    scene = load_scene(path)
    output = scene.data.get("output", {})
    directory = (
        Path(out) if out is not None else scene.directory / output.get("directory", ".")
    )
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    sets = study_sets(scene)
    if not sets:
        force, omega, kwargs = scene.frf_call()
        try:
            branch = hf.frf(scene.system(), force, omega, **kwargs)
        except (TypeError, ValueError) as exc:
            # a value of [frf] the load-time checks leave to frf (n_time,
            # aft, condense, ...): the message without a traceback
            raise _fail(f"{scene.name}: [frf]", str(exc)) from None
        progress(
            f"{scene.name}: {len(branch)} points, Ω {branch.omega.min():.6g}–"
            f"{branch.omega.max():.6g} rad/s, complete={branch.complete}, "
            f"{branch.elapsed:.3f} s"
        )
        if "csv" in output:
            written.append(
                _branch_csv(branch, directory / output["csv"], output.get("dof"))
            )
        if "npz" in output:
            written.append(Path(branch.save(directory / output["npz"])))
        if "png" in output:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            fig, ax = plt.subplots(figsize=(6, 4))
            # the CSV's quantity: the first harmonic (the plot's default,
            # half the peak-to-peak value, differed from the CSV beside it)
            branch.plot(ax=ax, harmonic=1, dof=output.get("dof"))
            _label_dof(ax, output.get("dof"))
            fig.savefig(directory / output["png"], dpi=120, bbox_inches="tight")
            plt.close(fig)
            written.append(directory / output["png"])
        result = {"branch": branch}
    else:
        st = scene.data["study"]
        force0, omega, kwargs = scene.frf_call()
        params = [{"frf.force": force0, **p} for p in sets]
        normal = st.get("normal_load", "contact.normal_load")
        res = hf.study(
            SceneBuilder(scene),
            params,
            omega,
            executor=st.get("executor", "processes"),
            workers=st.get("workers"),
            force_key="frf.force",
            normal_load_key=normal if any(normal in p for p in params) else None,
            progress=True,
            **kwargs,
        )
        progress(
            f"{scene.name}: {len(res)} FRFs, {len(res.failures)} failed, "
            f"{res.elapsed:.2f} s ({res.executor})"
        )
        dof = output.get("dof")  # the study's tables too (they ignored it)
        if "csv" in output:
            written.append(res.to_csv(directory / output["csv"], dof=dof))
        if "npz" in output:
            written.append(res.to_npz(directory / output["npz"], dof=dof))
        if "png" in output:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            fig, ax = plt.subplots(figsize=(6, 4))
            for r in res.runs:
                if r.ok:
                    r.branch.plot(
                        ax=ax,
                        harmonic=1,
                        dof=dof,
                        label=", ".join(
                            f"{k}={v:g}"
                            for k, v in r.parameters.items()
                            if isinstance(v, float | int)
                        ),
                    )
            ax.legend(fontsize=6)
            _label_dof(ax, dof)
            fig.savefig(directory / output["png"], dpi=120, bbox_inches="tight")
            plt.close(fig)
            written.append(directory / output["png"])
        result = {"study": res}
    for p in written:
        progress(f"wrote {p}")
    result["written"] = written
    return result


def _label_dof(ax, dof) -> None:
    """Name the plotted DOF in the title (default: the contact DOF)."""
    ax.set_title(f"DOF {dof!r}" if dof is not None else "contact DOF", fontsize=9)


def _branch_csv(branch, path: Path, dof=None) -> Path:
    """``omega`` (rad/s), ``amplitude`` (first-harmonic amplitude of
    ``dof``, default the contact DOF, m) and ``truncation_error`` per
    point: :meth:`hbmfric.Branch.to_csv`."""
    return branch.to_csv(path, dof)
