"""The zip from `make addon` installs as a Blender 5.0 extension (into a throw-away user
directory), loads its bundled core and renders a bundled scene with F12's operator."""

import os
import subprocess
import sys

from conftest import ROOT, SCENES_DIR

SCRIPT = """
import os, sys, bpy
bpy.ops.extensions.package_install_files(filepath=ZIP, repo="user_default", enable_on_install=True)
assert "bl_ext.user_default.ppm_render" in bpy.context.preferences.addons.keys()
bpy.ops.wm.open_mainfile(filepath=SCENE)
scene = bpy.context.scene
scene.ppm.passes, scene.ppm.photons_per_pass = 2, 20000
scene.render.resolution_percentage = 10
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.filepath = OUT
bpy.ops.render.render(write_still=True)
print("CORE", sys.modules["ppm_core"].__file__)
"""


def test_zip_installs_as_an_extension_and_renders(tmp_path):
    build = subprocess.run([sys.executable, os.path.join(ROOT, "addon", "build_addon.py"), "--out", str(tmp_path)],
                           capture_output=True, text=True, check=True)
    zip_path = build.stdout.split("wrote ")[1].split(" ")[0]
    out = tmp_path / "vase.exr"
    scene = os.path.join(SCENES_DIR, "bezier_vase.blend")
    script = f"ZIP, SCENE, OUT = {zip_path!r}, {scene!r}, {str(out)!r}\n" + SCRIPT
    env = {**os.environ, "BLENDER_USER_RESOURCES": str(tmp_path / "user")}
    run = subprocess.run([sys.executable, "-c", script], check=False, capture_output=True, text=True, timeout=300,
                         env=env, cwd=str(tmp_path))
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    core_line = next(line for line in run.stdout.splitlines() if line.startswith("CORE"))
    assert str(tmp_path / "user") in core_line  # the core inside the extension, not the .venv's
    assert out.exists() and out.stat().st_size > 0
