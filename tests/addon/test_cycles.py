"""Agreement with Cycles of the same Blender (5.0 here; 3.4 in tests/cli), one light kind at a time.

The mean radiance of 4x3 image blocks must agree within 3% (see cycles_compare.py for the scenes).
The numbers are the proof that light units and the camera match; no factor is tuned by eye.
"""

import pytest

import cycles_compare
from conftest import bpy  # noqa: F401 - registers the add-on


@pytest.mark.parametrize("kind", cycles_compare.kinds_for_this_blender())
def test_agrees_with_cycles(kind, tmp_path):
    row = cycles_compare.compare(kind, str(tmp_path), samples=128, passes=24)
    print(f"{kind}: Cycles {row['cycles_mean']:.5f} PPM {row['ppm_mean']:.5f} worst block "
          f"{100 * row['max_block_error']:.2f}%")
    assert row["max_block_error"] <= cycles_compare.TOLERANCE, row
