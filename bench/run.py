"""The benchmark harness: runs one experiment of bench/experiments/ and writes its report.

    .venv/bin/python bench/run.py                      # lists the experiments
    .venv/bin/python bench/run.py NAME [--quick] [--set key=value ...]

An experiment is data (bench/experiments/NAME.toml: its kind, a title, parameters); its kind is a
module of bench/kinds/. A full run writes bench/results/NAME/ (report.md, rows.json, plots); --quick
runs the file's [quick] parameters (a smoke run, figures meaningless) into bench/out/NAME/.
"""

from __future__ import annotations

import argparse
import importlib
import os
import shlex
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from harness import experiment as experiments  # noqa: E402
from harness.results import Results  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("name", nargs="?", help="an experiment (the stem of a file in bench/experiments/)")
    parser.add_argument("--quick", action="store_true", help="the experiment's [quick] parameters")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="override a parameter (TOML value; dotted keys reach into tables)")
    args = parser.parse_args(argv)
    if args.name is None:
        for name in experiments.available():
            e = experiments.load(name)
            print(f"{name:28s} {e.kind:12s} {e.title}")
        return 0
    experiment = experiments.load(args.name, args.quick, args.set)
    kind = importlib.import_module(f"kinds.{experiment.kind}")
    results = Results(experiment, "bench/run.py " + shlex.join(sys.argv[1:] if argv is None else argv))
    try:
        ok = kind.run(experiment, results)
    finally:
        results.close()
    return 0 if ok in (None, True) else 1


if __name__ == "__main__":
    sys.exit(main())
