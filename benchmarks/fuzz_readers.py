"""The long fuzz of every reader, and issue 19's target table.

Mutates real files from ../shared/data (tests/fuzzing.py: bit and byte flips, cuts,
insertions, deep nesting, hostile and plausible numbers), uses each as a user would
(reduce it, load it), flips bytes in a real project, and runs the hand-written hostile
cases of tests/test_hostile.py through the command line. Prints, per reader, how the
cases ended; the target is 0 raw tracebacks, 0 valid inputs refused, 0 results beyond
tolerance and 0 damaged projects loaded silently.

    .venv/bin/python benchmarks/fuzz_readers.py [--per-reader 3000] [--flips 2000] [--seed 19]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from typer.testing import CliRunner  # noqa: E402

from fuzzing import OUTCOMES, flip_bytes, fuzz, project_contents, real_project  # noqa: E402
from test_hostile import CLI_CASES  # noqa: E402

from sketchanim.cli import app  # noqa: E402


def hostile_cli() -> dict[str, int]:
    """The hostile command-line cases: how many exit 2 with no output, and how many end
    otherwise (a traceback, another status, or output written)."""
    runner = CliRunner()
    counts = {"named": 0, "traceback": 0}
    with tempfile.TemporaryDirectory() as tmp:
        for i, (name, text, extra, _) in enumerate(CLI_CASES.values()):
            folder = Path(tmp) / str(i)
            folder.mkdir()
            source = folder / name
            source.write_text(text, encoding="utf-8")
            out = folder / ("out.bvh" if name.endswith(".bvh") else "out.json")
            res = runner.invoke(app, ["reduce", str(source), "-o", str(out), *extra])
            clean = res.exit_code == 2 and (res.exception is None or isinstance(res.exception, SystemExit))
            counts["named" if clean and not out.exists() else "traceback"] += 1
    return counts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--per-reader", type=int, default=1000)
    parser.add_argument("--flips", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=19)
    parser.add_argument("--data", type=Path, default=Path(os.environ.get("SKETCHANIM_DATA", REPO.parent / "shared"
                                                                          / "data")))
    args = parser.parse_args()
    data = args.data if args.data.is_dir() else None
    clock = time.perf_counter()
    tally = fuzz(data, args.per_reader, args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        project = real_project(Path(tmp), data)
        flips = flip_bytes(project, project_contents(project), args.flips, args.seed)
    cli = hostile_cli()
    seconds = time.perf_counter() - clock

    print(f"mutations: {args.per_reader} per reader (+ the unmutated seed), seed {args.seed}, data "
          f"{data or 'absent: generated seeds'}; {seconds:.0f} s")
    print(f"{'reader':<12}" + "".join(f"{o:>17}" for o in OUTCOMES))
    rows = dict(tally.counts)
    rows["project flip"] = flips
    rows["hostile cli"] = cli
    for reader, counts in rows.items():
        print(f"{reader:<12}" + "".join(f"{counts.get(o, 0):>17}" for o in OUTCOMES))
    total = {o: sum(c.get(o, 0) for c in rows.values()) for o in OUTCOMES}
    print(f"{'all':<12}" + "".join(f"{total[o]:>17}" for o in OUTCOMES))
    print()
    print("target (all must be 0):")
    print(f"  raw tracebacks                     {total['traceback']}")
    print(f"  valid inputs refused               {total['refused_valid']}")
    print(f"  results beyond tolerance           {total['beyond_tolerance']}")
    print(f"  damaged projects loaded silently   {total['silent_damage']}")
    for example in tally.examples:
        print("  " + example.replace("\n", "\n    "))


if __name__ == "__main__":
    main()
