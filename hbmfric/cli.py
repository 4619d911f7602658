"""Command line: ``hbmfric paper [--out DIR]`` reproduces the paper's
results on the built-in scenes; ``hbmfric run scene.toml`` runs a scene
file."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def _paper(args: argparse.Namespace) -> int:
    from . import paper

    out = Path(args.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        kind = "an existing file" if out.is_file() else "not a usable directory"
        print(
            f"hbmfric paper: --out {str(out)!r} is {kind} ({exc.strerror or exc}); "
            "give a directory to write the results to",
            file=sys.stderr,
            flush=True,
        )
        return 2
    start = time.perf_counter()

    def progress(line: str) -> None:
        print(line, flush=True)

    h = args.harmonics

    def computed():
        # each figure is written as soon as it is computed, so that an error
        # (a full disk, a failing scene) never loses the ones before it
        from .warmup import PaperHelper

        # a first run: the beam's kernels compile meanwhile in a second
        # process (bench/README.md "Issue 17, stop 29")
        helper = PaperHelper.start(progress, args.lap_joint_pairs)
        try:
            yield from paper.iter_sdof_figures(harmonics=h, progress=progress)
        finally:
            if helper is not None:
                helper.wait(progress)
        yield paper.beam_normal_load_family(harmonics=h, progress=progress)
        yield paper.beam_ratio_family(harmonics=h, progress=progress)
        yield paper.beam_validation(harmonics=h, progress=progress)
        loop = paper.tensioner_loop(progress=progress)
        yield loop
        yield paper.tensioner_frf(loop.identification.law, progress=progress)
        # extra figure set, not the paper's (issue 15): the bolted lap joint
        if args.lap_joint_pairs:
            if helper is not None:
                helper.wait_lap_joint(progress)
            yield paper.lap_joint_family(args.lap_joint_pairs, progress=progress)

    figures = []
    entries = []
    index = out / "index.md"
    for fig in computed():
        figures.append(fig)
        verdict = _print_verdict(fig)
        if args.stability and _single_dof(fig):
            t = time.perf_counter()
            unstable = fig.stability()
            print(
                f"{fig.name}: stability by Hill's method, {unstable} unstable "
                f"point(s) ({time.perf_counter() - t:.1f} s)",
                flush=True,
            )
        try:
            written = [_write_csv(fig, out / f"{fig.name}.csv", args.resample)]
            if not args.no_plot:
                written.append(fig.write_png(out / f"{fig.name}.png"))
        except OSError as exc:
            print(
                f"hbmfric paper: cannot write {fig.name} to {str(out)!r} ({exc}); "
                f"stopped after {len(figures) - 1} figure(s) written",
                file=sys.stderr,
                flush=True,
            )
            return 1
        for path in written:
            print(f"wrote {path}", flush=True)
        entries.append((fig.name, [p.name for p in written], verdict))
        _write_index(index, entries, None)
    # the paper reads the beam's verdict from Figs. 13 (the stuck curve, the
    # envelope) and 14 (ratio invariance) together
    combined = _print_verdict(
        _combined(figures, ("fig13_beam", "fig14_beam"), "fig13+14_beam")
    )
    _write_index(index, entries, combined)
    print(f"index of the figures: {index}", flush=True)
    print(f"done in {time.perf_counter() - start:.2f} s", flush=True)
    return 0


def _single_dof(fig) -> bool:
    """A figure of single-DOF FRF branches (whose stability is cheap)."""
    branches = getattr(fig, "branches", None)
    return bool(branches) and all(b.coefficients.shape[1] == 1 for b in branches)


#: what each figure shows, and the claim of the paper it checks
FIGURES = {
    "fig03_tensioner_loop": (
        "hysteresis loop of the belt tensioner and the modified Dahl law "
        "identified from it (envelope lines by least squares, beta from the loop)",
        "Sec. 2: the modified Dahl law reproduces the tensioner's loop",
    ),
    "fig05_tensioner_frf": (
        "belt-tension variation |max T - min T| against forcing frequency at "
        "several forcing amplitudes, harmonic balance against time integration",
        "Sec. 2: stuck at low forcing, slipping at high forcing, bounded tension "
        "over a band, softening, a subharmonic resonance at a third of the stuck one",
    ),
    "fig08_masing": (
        "single-DOF FRFs per unit force with a Jenkins (Masing macroslip) contact, "
        "Fex/Fn = 10, 0.5, 0.2, 0.1, 0.001",
        "Sec. 3.1: FRFs depend on Fex/Fn only; mostly stuck curves stay inside the "
        "fully stuck envelope (criterion: macroslip)",
    ),
    "fig09_menq": (
        "the same family with a Menq microslip contact",
        "Sec. 3.1: mostly stuck curves move to lower frequency, out of the stuck "
        "envelope (criterion: microslip)",
    ),
    "fig10_masing_roughness": (
        "the Masing family with roughness, Fex = 1 N and 1000 N at each ratio",
        "Sec. 3.1: with roughness the curves move to lower frequency and are no "
        "longer a function of Fex/Fn alone",
    ),
    "fig11_menq_roughness": (
        "the Menq family with roughness, Fex = 1 N and 1000 N at each ratio",
        "Sec. 3.1: as Fig. 10, for microslip",
    ),
    "fig13_beam_normal_load": (
        "tip FRFs of the clamped beam at Fex = 2 N, Fn from 40 N to 0.5 N",
        "Sec. 3.2: linear and stuck at 87 Hz (Fn = 40 N), flat at Fn = 1 N, full "
        "slip at 24 Hz (Fn = 0.5 N)",
    ),
    "fig14_beam_ratios": (
        "beam FRFs per unit force at Fex/Fn = 0.5, 1, 2 (Fn = 2.5, 3, 5, 10 N)",
        "Sec. 3.2: the twelve configurations collapse by ratio: macroslip without "
        "roughness",
    ),
    "extra_lapjoint": (
        "EXTRA, NOT IN THE PAPER: drive-point FRFs of a bolted lap joint "
        "(Brake-Reuss-like, one Jenkins contact per interface node pair) at "
        "Fex/P from 2e-5 to 4e-2 (P the total bolt preload), at two preloads",
        "not a claim of the paper: its criterion applied to a joint with many "
        "contacts (docs/lap-joint.md)",
    ),
    "fig15_beam_validation": (
        "beam FRFs by harmonic balance with time-integration points",
        "Sec. 3.2: the harmonic balance matches the reference response",
    ),
}


def _describe(name: str) -> tuple[str, str]:
    for key, text in FIGURES.items():
        if name.startswith(key):
            return text
    return ("", "")


def _write_index(path: Path, entries, combined: str | None) -> None:
    """The Markdown index of the figures written so far (rewritten after
    each, so that an interrupted run still has one)."""
    lines = [
        "# hbmfric paper: the figures",
        "",
        "Reproduction of Chatelet, Michon, Manin & Jacquet, *Stick/slip phenomena "
        "in dynamics: choice of contact model*, Mechanism and Machine Theory 43 "
        "(2008). One line per figure: what it shows, and the paper's claim it "
        "checks (with the contact-model criterion's verdict where it applies).",
        "",
        "| figure | files | what it shows | claim checked | criterion |",
        "|---|---|---|---|---|",
    ]
    for name, files, verdict in entries:
        shows, claim = _describe(name)
        links = ", ".join(f"[{f}]({f})" for f in files)
        lines.append(f"| {name} | {links} | {shows} | {claim} | {verdict or ''} |")
    if combined:
        lines += ["", f"Beam, Figs. 13 and 14 read together: {combined}."]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def _warmup(args: argparse.Namespace) -> int:
    from .warmup import warmup

    warmup(progress=lambda line: print(line, flush=True), jobs=args.jobs)
    return 0


def _run(args: argparse.Namespace) -> int:
    from .scene import SceneError, run_scene

    try:
        result = run_scene(
            args.scene, args.out, progress=lambda line: print(line, flush=True)
        )
    except FileNotFoundError as exc:
        print(f"hbmfric run: {exc}", file=sys.stderr, flush=True)
        return 2
    except SceneError as exc:
        print(f"hbmfric run: {exc}", file=sys.stderr, flush=True)
        return 2
    except MemoryError as exc:
        # the memory guard's refusal of a model too large for the machine
        # (with what to do): the message, not a traceback above it
        print(f"hbmfric run: {args.scene}: {exc}", file=sys.stderr, flush=True)
        return 2
    study = result.get("study")
    if study is not None and study.failures:
        # the others are written; a script (make, CI) must still see it
        first = study.failures[0]
        print(
            f"hbmfric run: {len(study.failures)} of {len(study)} parameter sets "
            f"failed (first: set {first.index} {first.parameters}: {first.error}); "
            "the others are written",
            file=sys.stderr,
            flush=True,
        )
        return 1
    return 0


def _write_csv(fig, path, resample):
    """A figure's CSV; the FRF families (branches) at ``resample`` dense
    samples per interval when asked."""
    from .paper.sdof import FigureResult

    if resample is not None and isinstance(fig, FigureResult):
        return fig.write_csv(path, resample=resample)
    return fig.write_csv(path)


def _resample_arg(value: str) -> int:
    """A positive integer (``--resample``, ``--jobs``)."""
    try:
        k = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"must be a positive integer, got {value!r}"
        ) from None
    if k < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {k}")
    return k


def _combined(figures, prefixes, name):
    """One family made of the figures named ``prefixes…`` (None unless all
    are there)."""
    from .paper.sdof import FigureResult

    parts = [f for p in prefixes for f in figures if f.name.startswith(p)]
    if len(parts) != len(prefixes):
        return None
    return FigureResult(
        name,
        name,
        [lab for f in parts for lab in f.labels],
        [b for f in parts for b in f.branches],
        [par for f in parts for par in f.parameters],
    )


def _print_verdict(fig) -> str | None:
    """One line: the contact-model criterion's verdict on a computed family
    (figures that are not FRF families, without ``criterion``, are skipped);
    returns it (None when skipped)."""
    if fig is None:
        return None
    params = getattr(fig, "parameters", None) or [{}]
    if not hasattr(fig, "criterion") or not all(
        "normal_load" in p and "force" in p for p in params
    ):
        return None
    try:
        res = fig.criterion()
    except ValueError as err:  # e.g. a curve with zero amplitude somewhere
        print(f"{fig.name} criterion: not applicable ({err})", flush=True)
        return f"not applicable ({err})"
    ind = res.indicators
    parts = []
    if ind.get("ratio_spread") is not None:
        parts.append(f"ratio spread {ind['ratio_spread']:.2g}")
    if ind.get("envelope_excess") is not None:
        parts.append(f"envelope excess {100 * ind['envelope_excess']:.1f} %")
    shifts = ind.get("peak_shift") or {}
    if shifts:
        parts.append(
            "peak shifts "
            + ", ".join(f"{100 * v:+.1f} % (Fex/Fn={r:.3g})" for r, v in shifts.items())
        )
    text = res.verdict + (f" ({'; '.join(parts)})" if parts else "")
    print(f"{fig.name} criterion: {text}", flush=True)
    return text


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``hbmfric`` console script."""
    parser = argparse.ArgumentParser(
        prog="hbmfric",
        description="Harmonic balance for structures with dry-friction contacts.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    sub = parser.add_subparsers(dest="command", required=True)
    paper = sub.add_parser(
        "paper",
        help="reproduce the paper's figures (Chatelet et al. 2008)",
        description="Compute the paper's FRF families; write a CSV and a PNG "
        "per figure.",
    )
    paper.add_argument(
        "--out",
        default="paper-results",
        help="output directory (default: paper-results)",
    )
    paper.add_argument(
        "--harmonics",
        type=_harmonics_arg,
        default="auto",
        help="highest harmonic, or 'auto' (default: chosen along each branch "
        "for a relative truncation error below 1e-4)",
    )
    paper.add_argument("--no-plot", action="store_true", help="write CSV files only")
    paper.add_argument(
        "--resample",
        type=_resample_arg,
        default=None,
        metavar="K",
        help="write the FRF curves' dense output (K samples per interval "
        "between computed points, a 'computed' column flags the points) "
        "instead of the computed points alone",
    )
    paper.add_argument(
        "--lap-joint-pairs",
        type=_pairs_arg,
        default=10,
        metavar="N",
        help="contact node pairs of the extra lap-joint figure set (not in the "
        "paper; default 10: about 7 s warm, 40: about 50 s warm, on two cores), "
        "0 to skip it",
    )
    paper.add_argument(
        "--stability",
        action="store_true",
        help="also compute the stability of every point of the single-DOF "
        "figures (Hill's method) and add a 'stable' column to their CSV "
        "(the beam's and the tensioner's figures are left without it: "
        "their full Hill problems cost minutes)",
    )
    paper.set_defaults(func=_paper)
    run = sub.add_parser(
        "run",
        help="run a scene file (TOML): a system, its contact, an FRF or a study",
        description="Trace the FRF (or the study grid) a scene file describes and "
        "write its outputs. The format (tables, keys, units) is in the "
        "documentation page 'Scene files and studies' (docs/scenes-and-studies.md); "
        "examples in examples/scenes/.",
    )
    run.add_argument("scene", help="the scene file (.toml)")
    run.add_argument(
        "--out", default=None, help="output directory (overrides the file)"
    )
    run.set_defaults(func=_run)
    warm = sub.add_parser(
        "warmup",
        help="compile (or load) the kernels typical runs use, once, now",
        description="Run a tiny problem through each path of the engine so that "
        "the one-time Numba compilation happens now rather than in the first "
        "real run (e.g. after pip install, or in a container build).",
    )
    warm.add_argument(
        "--jobs",
        type=_resample_arg,
        default=1,
        help="worker processes that compile at once (default 1; 2 on two "
        "cores about halves the wait)",
    )
    warm.set_defaults(func=_warmup)
    args = parser.parse_args(argv)
    return args.func(args)


def _version() -> str:
    """The installed version (the package metadata's, else the module's)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("hbmfric")
    except PackageNotFoundError:
        import hbmfric

        return getattr(hbmfric, "__version__", "unknown")


def _pairs_arg(text: str) -> int:
    """``--lap-joint-pairs``: 0 (skip) or an integer >= 2."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"must be 0 or an integer >= 2, got {text!r}"
        ) from None
    if value != 0 and value < 2:
        raise argparse.ArgumentTypeError(f"must be 0 or >= 2, got {value}")
    return value


def _harmonics_arg(text: str) -> int | str:
    """``--harmonics``: a positive integer or ``auto``."""
    if text == "auto":
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"must be a positive integer or 'auto', got {text!r}"
        ) from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {value}")
    return value


if __name__ == "__main__":
    sys.exit(main())
