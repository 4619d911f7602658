"""Command line: ``hbmfric paper [--out DIR]`` reproduces the paper's
results on the built-in scenes."""

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
        yield from paper.iter_sdof_figures(harmonics=h, progress=progress)
        yield paper.beam_normal_load_family(harmonics=h, progress=progress)
        yield paper.beam_ratio_family(harmonics=h, progress=progress)
        yield paper.beam_validation(harmonics=h, progress=progress)
        loop = paper.tensioner_loop(progress=progress)
        yield loop
        yield paper.tensioner_frf(loop.identification.law, progress=progress)

    figures = []
    for fig in computed():
        figures.append(fig)
        _print_verdict(fig)
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
    # the paper reads the beam's verdict from Figs. 13 (the stuck curve, the
    # envelope) and 14 (ratio invariance) together
    _print_verdict(_combined(figures, ("fig13_beam", "fig14_beam"), "fig13+14_beam"))
    print(f"done in {time.perf_counter() - start:.2f} s", flush=True)
    return 0


def _write_csv(fig, path, resample):
    """A figure's CSV; the FRF families (branches) at ``resample`` dense
    samples per interval when asked."""
    from .paper.sdof import FigureResult

    if resample is not None and isinstance(fig, FigureResult):
        return fig.write_csv(path, resample=resample)
    return fig.write_csv(path)


def _resample_arg(value: str) -> int:
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


def _print_verdict(fig) -> None:
    """One line: the contact-model criterion's verdict on a computed family
    (figures that are not FRF families, without ``criterion``, are skipped)."""
    if fig is None:
        return
    params = getattr(fig, "parameters", None) or [{}]
    if not hasattr(fig, "criterion") or not all(
        "normal_load" in p and "force" in p for p in params
    ):
        return
    try:
        res = fig.criterion()
    except ValueError as err:  # e.g. a curve with zero amplitude somewhere
        print(f"{fig.name} criterion: not applicable ({err})", flush=True)
        return
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
    print(
        f"{fig.name} criterion: {res.verdict}"
        + (f" ({'; '.join(parts)})" if parts else ""),
        flush=True,
    )


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``hbmfric`` console script."""
    parser = argparse.ArgumentParser(
        prog="hbmfric",
        description="Harmonic balance for structures with dry-friction contacts.",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    paper = sub.add_parser(
        "paper",
        help="reproduce the paper's figures (Chatelet et al. 2008)",
        description="Compute the paper's FRF families; write a CSV and a PNG "
        "per figure.",
    )
    paper.add_argument("--out", default="paper-results", help="output directory")
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
    paper.set_defaults(func=_paper)
    args = parser.parse_args(argv)
    return args.func(args)


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
