"""The zip from `make addon` installs into a clean Blender 3.4 user directory as a legacy add-on,
loads its bundled core (not this checkout's) and renders with F12's operator."""

import os
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "blend_scenes", "bezier_vase.blend")

pytestmark = pytest.mark.skipif(shutil.which("blender") is None, reason="needs Debian's blender")

SCRIPT = """
import sys, bpy
bpy.ops.preferences.addon_install(filepath=ZIP)
bpy.ops.preferences.addon_enable(module="ppm_render")
bpy.ops.wm.open_mainfile(filepath=SCENE)
scene = bpy.context.scene
scene.render.engine = "PPM"
scene.ppm.passes, scene.ppm.photons_per_pass = 2, 20000
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 64, 48, 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.filepath = OUT
bpy.ops.render.render(write_still=True)
print("CORE", sys.modules["ppm_core"].__file__)
"""


def test_zip_installs_and_renders_in_blender_34(tmp_path):
    build = subprocess.run([sys.executable, os.path.join(ROOT, "addon", "build_addon.py"), "--out", str(tmp_path)],
                           capture_output=True, text=True, check=True)
    zip_path = build.stdout.split("wrote ")[1].split(" ")[0]
    out = tmp_path / "vase.exr"
    script = f"ZIP, SCENE, OUT = {zip_path!r}, {SCENE!r}, {str(out)!r}\n" + SCRIPT
    env = {**os.environ, "BLENDER_USER_SCRIPTS": str(tmp_path / "scripts"),
           "BLENDER_USER_CONFIG": str(tmp_path / "config")}
    run = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python-expr", script],
                         check=False, capture_output=True, text=True, timeout=300, env=env)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    core_line = next(line for line in run.stdout.splitlines() if line.startswith("CORE"))
    assert str(tmp_path / "scripts") in core_line  # the bundled core, not the checkout's .venv
    assert out.exists() and out.stat().st_size > 0
