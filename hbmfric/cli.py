"""Command line: ``hbmfric paper [--out DIR]`` reproduces the paper's
results on the built-in scenes."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path


def _paper(args: argparse.Namespace) -> int:
    from .paper import masing_family, tensioner_frf, tensioner_loop

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()

    def progress(line: str) -> None:
        print(line, flush=True)

    figures = [masing_family(harmonics=args.harmonics, progress=progress)]
    loop = tensioner_loop(progress=progress)
    figures += [loop, tensioner_frf(loop.identification.law, progress=progress)]
    for fig in figures:
        csv_path = fig.write_csv(out / f"{fig.name}.csv")
        print(f"wrote {csv_path}", flush=True)
        if not args.no_plot:
            png_path = fig.write_png(out / f"{fig.name}.png")
            print(f"wrote {png_path}", flush=True)
    print(f"done in {time.perf_counter() - start:.2f} s", flush=True)
    return 0


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
        "--harmonics", type=int, default=15, help="highest harmonic (default 15)"
    )
    paper.add_argument("--no-plot", action="store_true", help="write CSV files only")
    paper.set_defaults(func=_paper)
    args = parser.parse_args(argv)
    if getattr(args, "harmonics", 1) < 1:
        parser.error("--harmonics must be >= 1")
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
