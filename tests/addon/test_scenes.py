"""Every bundled .blend renders through the engine at low resolution: non-empty, finite, plausible."""

import os

import numpy as np
import pytest

from conftest import SCENES_DIR, bpy, render_file

SCENES = ("cornell_3spheres", "bezier_vase", "cornell_dof", "showcase", "cornell_diffuse", "hdri_glass",
          "fog_caustic", "fog_shafts", "cloud", "studio")


@pytest.mark.parametrize("name", SCENES)
def test_bundled_scene_renders(name, tmp_path):
    path = os.path.join(SCENES_DIR, f"{name}.blend")
    assert os.path.isfile(path), f"{path} missing: run make blend-scenes"
    bpy.ops.wm.open_mainfile(filepath=path)
    scene = bpy.context.scene
    assert scene.render.engine == "PPM"
    scene.render.resolution_percentage = 12  # 640x480 -> 76x57: resolution percentage respected
    image = render_file(scene, tmp_path / f"{name}.exr", passes=3, photons_per_pass=30_000, samples_per_pixel=1)
    assert image.shape == (57, 76, 4)
    rgb = image[..., :3]
    assert np.isfinite(rgb).all() and (rgb >= 0).all()
    lit = (rgb.mean(axis=2) > 1e-3).mean()
    assert lit > 0.5, f"only {lit:.0%} of the pixels receive light"
    assert 0.01 < rgb.mean() < 50.0
    assert rgb.std() > 0.01  # an image, not a constant


def gradient_energy(rgb):
    lum = rgb.mean(axis=2)
    return float(np.abs(np.diff(lum, axis=0)).mean() + np.abs(np.diff(lum, axis=1)).mean())


def test_depth_of_field_modes_reach_the_core(tmp_path):
    """cornell_dof: POST blurs the same render (less gradient energy than OFF), LENS renders a different image."""
    path = os.path.join(SCENES_DIR, "cornell_dof.blend")
    images = {}
    for mode in ("OFF", "POST", "LENS"):
        bpy.ops.wm.open_mainfile(filepath=path)
        scene = bpy.context.scene
        assert scene.camera.data.dof.use_dof
        scene.render.resolution_percentage = 100  # at 15% f/1.4 blurs less than a pixel: the core skips DoF
        images[mode] = render_file(scene, tmp_path / f"dof_{mode}.exr", passes=2, photons_per_pass=20_000,
                                   samples_per_pixel=1, dof_mode=mode)[..., :3]
        assert np.isfinite(images[mode]).all()
    # Same seed, same base image: any drop in gradient energy is the blur (in-focus parts stay sharp).
    assert gradient_energy(images["POST"]) < 0.95 * gradient_energy(images["OFF"])
    assert np.abs(images["LENS"] - images["OFF"]).mean() > 0.01 * images["OFF"].mean()


def window_mean(scene, rgb, point, half=1):
    """Mean luminance of the (2 half + 1)^2 pixels around where the camera sees `point`."""
    from bpy_extras.object_utils import world_to_camera_view  # importable once bpy is (conftest)
    from mathutils import Vector

    v = world_to_camera_view(scene, scene.camera, Vector(point))
    height, width = rgb.shape[:2]
    x, y = int(v.x * width), int((1.0 - v.y) * height)
    assert half <= x < width - half and half <= y < height - half, (point, x, y)
    return float(rgb[y - half:y + half + 1, x - half:x + half + 1].mean())


def test_fog_caustic_has_a_caustic_spot_on_the_floor(tmp_path):
    """fog_caustic: the light the glass ball focuses, from photons alone (direct light cannot pass glass),
    is brighter on the floor where the spot's axis lands than on the floor 0.8 m in front of and behind
    that spot (the floor there is lit by the fill light and the fog only)."""
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SCENES_DIR, "fog_caustic.blend"))
    scene = bpy.context.scene
    scene.render.resolution_percentage = 25  # 160x120: the cone is 4-6 pixels wide
    rgb = render_file(scene, tmp_path / "fog_caustic.exr", passes=16, photons_per_pass=100_000)[..., :3]
    ball = np.array(bpy.data.objects["glass_ball"].location)
    axis = ball - np.array(bpy.data.objects["spot"].location)
    axis /= np.linalg.norm(axis)
    beam = ball + 0.85 * axis  # between the ball (radius 0.5) and the floor, near the focus
    beside = beam * (-1.0, 1.0, 1.0)  # mirrored in the ball's upright plane x = 0: fog out of every shaft
    floor = ball + ball[2] / -axis[2] * axis
    around = [floor + (0.0, dy, 0.0) for dy in (-0.8, 0.8)]
    beam_lum, beside_lum = window_mean(scene, rgb, beam), window_mean(scene, rgb, beside)
    floor_lum = window_mean(scene, rgb, floor)
    around_lum = max(window_mean(scene, rgb, p) for p in around)
    print(f"beam {beam_lum:.4f} beside {beside_lum:.4f} floor caustic {floor_lum:.4f} around {around_lum:.4f}")
    assert floor_lum > 10.0 * around_lum  # measured 43 times (1.12 against 0.026)
    # Not asserted yet: the cone in the fog. Measured 0.0034 behind the ball against 0.0048 beside it
    # (bpy 5.0, this render): the volume photons behind the glass do not yet make the cone stand out.
