"""render.py from a shell with Debian's Blender 3.4 binary (and the bpy module for comparison)."""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RENDER = os.path.join(ROOT, "render.py")
SCENE = os.path.join(ROOT, "blend_scenes", "cornell_3spheres.blend")
BLENDER = shutil.which("blender")
ARGS = ["--passes", "3", "--resolution", "64", "48", "--photons", "30000", "--seed", "5"]

pytestmark = pytest.mark.skipif(BLENDER is None, reason="Debian's blender is installed by tools/setup.sh")


def blender(*args, timeout=300):
    cmd = [BLENDER, "-b", *args]
    return subprocess.run(cmd, check=False, capture_output=True, text=True, timeout=timeout, cwd=ROOT)


def read_exr(path):
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(str(path))
    assert not buf.has_error, buf.geterror()
    return buf.get_pixels(oiio.FLOAT)


def test_blender_34_renders_a_bundled_scene(tmp_path):
    out = tmp_path / "cornell.exr"
    run = blender("--python-exit-code", "1", "-P", RENDER, "--", SCENE, "--output", str(out), *ARGS)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    assert "Blender 3.4" in run.stdout and "render.py: wrote" in run.stdout
    # The file is read once the engine is registered: no "Engine 'PPM' not available" error first.
    assert "not available" not in run.stdout + run.stderr, run.stdout[-2000:] + run.stderr[-2000:]
    image = read_exr(out)
    assert image.shape == (48, 64, 4)
    assert np.isfinite(image).all() and 0.02 < image[..., :3].mean() < 10
    # The same file through the bpy module (Blender 5.0) and the same core gives the same picture.
    out5 = tmp_path / "cornell5.exr"
    run5 = subprocess.run([sys.executable, RENDER, SCENE, "--output", str(out5), *ARGS], check=False,
                          capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert run5.returncode == 0, run5.stderr[-2000:]
    assert "not available" not in run5.stdout + run5.stderr, run5.stdout[-2000:] + run5.stderr[-2000:]
    image5 = read_exr(out5)
    assert image[..., :3].mean() == pytest.approx(image5[..., :3].mean(), rel=0.02)


@pytest.mark.parametrize("case", ["missing_file", "corrupt_file", "bad_output", "no_camera"])
def test_broken_input_fails_with_a_readable_message(case, tmp_path):
    out = str(tmp_path / "out.exr")
    # Blender itself refuses unreadable files (before render.py runs), with its own message.
    if case == "missing_file":
        blend, expected = str(tmp_path / "nope.blend"), "Cannot read file"
    elif case == "corrupt_file":
        blend, expected = str(tmp_path / "corrupt.blend"), "Failed to read blend file"
        with open(blend, "wb") as f:
            f.write(b"BLENDER-v304 this is not a blend file" * 10)
    elif case == "bad_output":
        blend, out, expected = SCENE, str(tmp_path / "out.jpg"), "use a .exr or .png"
    else:  # the one thing a frame cannot do without (the engine renders around bad objects)
        blend, expected = str(tmp_path / "nocamera.blend"), "Cannot render, no camera"
        script = (f"import bpy; bpy.ops.wm.open_mainfile(filepath={SCENE!r}); bpy.context.scene.camera = None; "
                  f"bpy.ops.wm.save_as_mainfile(filepath={blend!r})")
        assert blender("--factory-startup", "--python-expr", script).returncode == 0
    run = blender(blend, "--python-exit-code", "1", "-P", RENDER, "--", "--output", out, *ARGS)
    assert run.returncode != 0
    output = run.stdout + run.stderr
    assert expected in output, output[-2000:]
    if case in ("bad_output", "no_camera"):
        assert "render.py: error:" in run.stderr


def test_python_mode_reports_a_missing_file(tmp_path):
    run = subprocess.run([sys.executable, RENDER, str(tmp_path / "nope.blend"), "--output", str(tmp_path / "o.exr")],
                         check=False, capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert run.returncode == 1 and "render.py: error:" in run.stderr and "does not exist" in run.stderr
