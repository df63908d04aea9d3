"""The route through several Blender versions: a function of a bench/ module called in a child process
of one version's Python (the bpy module of each: .venv for 5.0, .venvs/bpy-<version> for the others,
as the Makefile has them). Arguments and result travel as JSON, so that the harness itself can run in
any of them and a crash in Blender only ends the child."""

from __future__ import annotations

import json
import os
import subprocess

BENCH = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(BENCH)
MARK = "BENCH-RESULT "

# Imports "module:function" from bench/, calls it with the JSON on stdin, prints its JSON result.
CHILD = f"""
import importlib, json, sys
sys.path.insert(0, {BENCH!r})
module, name = sys.argv[1].split(":")
result = getattr(importlib.import_module(module), name)(json.load(sys.stdin))
print({MARK!r} + json.dumps(result), flush=True)
"""


def python_of(blender):
    """The Python executable whose bpy module is Blender `blender` ("5.0", "4.2", ...)."""
    venv = ".venv" if blender == "5.0" else os.path.join(".venvs", f"bpy-{blender}")
    path = os.path.join(ROOT, venv, "bin", "python")
    if not os.path.exists(path):
        raise SystemExit(f"no Python for Blender {blender}: {path} is missing")
    return path


def call(blender, function, params=None, cwd=ROOT, timeout=None):
    """Calls `function` ("kinds.name:function") with `params` in Blender `blender`'s Python; returns
    (its result, or None if the child failed, and the finished process). `cwd` must hold no file
    named like a standard module (`import bpy` aborts then): the repository root or a clean folder."""
    process = subprocess.run([python_of(blender), "-c", CHILD, function], input=json.dumps(params or {}),
                             capture_output=True, text=True, cwd=cwd, timeout=timeout)
    lines = [line for line in process.stdout.splitlines() if line.startswith(MARK)]
    result = json.loads(lines[-1][len(MARK):]) if process.returncode == 0 and lines else None
    return result, process


def result_of(blender, function, params=None, **options):
    """As `call`, but a failed child is an error (with the end of its output)."""
    result, process = call(blender, function, params, **options)
    if result is None:
        raise RuntimeError(f"{function} in Blender {blender} failed (exit {process.returncode}):\n"
                           f"{process.stdout[-2000:]}\n{process.stderr[-2000:]}")
    return result
