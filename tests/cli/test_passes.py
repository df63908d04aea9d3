"""Depth and Normal passes (Blender 3.4 binary): the PPM passes agree with Cycles' (passes_compare.py)."""

import json
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

pytestmark = pytest.mark.skipif(shutil.which("blender") is None, reason="needs Debian's blender")


def test_depth_and_normal_passes_match_cycles(tmp_path):
    script = os.path.join(ROOT, "tests", "cli", "passes_compare.py")
    run = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "-P", script, "--",
                          str(tmp_path)], check=False, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    figures = json.loads((tmp_path / "passes.json").read_text())
    assert figures["shape"] == [36, 48]
    assert figures["smooth_fraction"] > 0.8
    assert figures["max_depth_error"] < 0.01
    assert figures["median_normal_dot"] > 0.999 and figures["normals_within_11deg"] > 0.95
