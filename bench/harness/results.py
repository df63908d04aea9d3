"""Where an experiment's figures go: bench/results/<experiment>/ for a full run (report.md, the tables
as printed; rows.json; plots), bench/out/<experiment>/ for a quick one (not the README's figures).
Everything printed to the report is also printed to the terminal as it comes."""

from __future__ import annotations

import datetime
import json
import os
import platform
import subprocess
import sys

BENCH_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(BENCH_DIR)


def git_commit():
    try:
        out = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"], capture_output=True, text=True)
        return out.stdout.strip() or "unknown"
    except OSError:
        return "unknown"


class Results:
    def __init__(self, experiment, command):
        top = os.path.join(BENCH_DIR, "out" if experiment.quick else "results")
        self.folder = os.path.join(top, experiment.name)
        os.makedirs(self.folder, exist_ok=True)
        self.rows = []
        self._report = open(os.path.join(self.folder, "report.md"), "w")
        load = os.getloadavg()[0]
        self.note(f"# {experiment.title}\n\n`{command}`: {datetime.date.today().isoformat()}, commit "
                  f"{git_commit()}, {os.cpu_count()} cores ({platform.processor() or platform.machine()}), "
                  f"load {load:.1f} at the start, Python {sys.version.split()[0]}.")

    def note(self, text=""):
        """A paragraph of the report."""
        print(text, flush=True)
        self._report.write(text + "\n")
        self._report.flush()

    def table(self, header, rows, title=None):
        """A markdown table: `header` a list of column names, `rows` lists of cells (formatted strings)."""
        lines = ([f"\n### {title}\n"] if title else [""]) + ["| " + " | ".join(header) + " |",
                                                              "|" + "---|" * len(header)]
        lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
        self.note("\n".join(lines))

    def row(self, **fields):
        """One measured row, kept for rows.json (what plots and later analyses read)."""
        self.rows.append(fields)

    def path(self, filename):
        """A file in the results folder (plots, images)."""
        return os.path.join(self.folder, filename)

    def close(self):
        if self.rows:
            with open(self.path("rows.json"), "w") as f:
                json.dump(self.rows, f, indent=1)
        self.note(f"\nresults: {os.path.relpath(self.folder, ROOT)}/")
        self._report.close()
