"""A still's passes as shares on dask.distributed (addon/ppm_render/farm): the merge equals one
render of all the passes, a killed worker's share runs again, a deadline returns what came back."""

import dataclasses
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy  # noqa: E402  (installed by make setup; a missing bpy must fail, not skip)

import ppm_render  # noqa: E402
from ppm_render import core  # noqa: E402
from ppm_render.farm import shares  # noqa: E402
from ppm_render.farm.merge import ProgressiveMerge, submit_shares  # noqa: E402
from ppm_render.farm.still_export import export_still  # noqa: E402

# The fixtures are here, not in a conftest.py: tests/addon's tests import theirs by that module name,
# and `make test` runs both folders in one session.


@pytest.fixture(scope="session")
def ppm_core():
    return core.load()


def bundled_still(ppm_core, blend, width, height, **ppm):
    """A bundled .blend at width x height with these scene.ppm settings, exported as the farm exports
    it; its warnings in `warnings`."""
    registered_here = not hasattr(bpy.types.Scene, "ppm")  # tests/addon's fixtures may have registered it
    if registered_here:
        ppm_render.register()
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "blend_scenes", blend))
        render = bpy.context.scene.render
        render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
        for key, value in ppm.items():
            setattr(bpy.context.scene.ppm, key, value)
        warnings = []
        exported = export_still(bpy, ppm_core, warnings.append)
        exported.warnings = warnings
        return exported
    finally:
        if registered_here:  # bpy 4.2 crashes and 4.5 hangs at exit while a script's classes are registered
            ppm_render.unregister()


@pytest.fixture(scope="session")
def still(ppm_core):
    """cornell_diffuse.blend at 48x36, exported as the farm exports it; its warnings in `warnings`. Its
    target error is the merged image's: no share may stop on it."""
    return bundled_still(ppm_core, "cornell_diffuse.blend", 48, 36, photons_per_pass=20_000, target_error=0.05)


@pytest.fixture(scope="module")
def cluster():
    """Two worker processes with one thread each, as a farm's machines (no dashboard)."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as local, \
            Client(local) as client:
        yield client


def single_render(still, passes):
    """All the passes in one renderer here, as a Share: what the merge must equal."""
    return shares.render_share(still.calls, still.settings, 0, passes)[0]


def read_exr_with_header(path):
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    assert not buf.has_error, buf.geterror()
    spec = buf.spec()
    header = {name: spec.getattribute(name) for name in ("ppm:passes", "ppm:shares", "ppm:error_relative")}
    return buf.get_pixels(oiio.FLOAT), header


def merged_image(client, still, passes, count, tmp_path, **collect):
    lines = []
    merge = ProgressiveMerge(str(tmp_path / "out.exr"), count, 1e9, lines.append)
    futures = submit_shares(client, still, passes, count, threads=1)
    merge.collect(futures, **collect)
    return merge, lines


def test_plan_covers_every_pass_once():
    for total, count in [(10, 3), (64, 64), (5, 8), (1000, 7)]:
        ranges = shares.plan(total, count)
        assert [f for f, _ in ranges] == sorted(f for f, _ in ranges)
        assert sum(n for _, n in ranges) == total and all(n >= 1 for _, n in ranges)
        assert all(a + n == b for (a, n), (b, _) in zip(ranges, ranges[1:]))
        assert max(n for _, n in ranges) - min(n for _, n in ranges) <= 1
    with pytest.raises(ValueError):
        shares.plan(0, 4)


def test_the_export_is_a_share_render(still):
    assert still.settings["radius_schedule"] == "global" and still.settings["hit_points"] == "stochastic"
    assert still.settings["target_error"] == 0.0 and still.target_error == pytest.approx(0.05)
    assert (still.width, still.height) == (48, 36)
    names = {call[0] for call in still.calls}
    assert {"add_mesh", "add_material", "add_light", "set_camera"} <= names
    assert not names & {"intersect", "run_program", "texture_info"}  # queries are not replayed


def test_merged_shares_equal_one_render(ppm_core, still, cluster, tmp_path):
    merge, lines = merged_image(cluster, still, 8, 4, tmp_path)
    assert merge.finish()
    assert merge.merged.passes == 8 and merge.merged.ranges == [(0, 2), (2, 2), (4, 2), (6, 2)]
    single = single_render(still, 8)
    np.testing.assert_allclose(merge.merged.image(), single.image(), rtol=1e-5, atol=1e-6 * single.image().max())
    assert merge.merged.error_stats()["relative"] == pytest.approx(single.error_stats()["relative"], rel=1e-4)
    assert any("4/4 shares" in line for line in lines)
    pixels, header = read_exr_with_header(str(tmp_path / "out.exr"))
    np.testing.assert_array_equal(pixels, merge.merged.image())
    assert header["ppm:passes"] == 8 and header["ppm:shares"] == 4
    assert header["ppm:error_relative"] == pytest.approx(merge.merged.error_stats()["relative"], rel=1e-6)


def test_workers_need_no_blender(still, cluster):
    futures = submit_shares(cluster, still, 2, 2, threads=1)
    for future in futures:
        _, facts = future.result()
        assert facts["bpy_loaded"] is False
    # Nor this add-on: its package imports bpy.
    assert not any(cluster.run(lambda: __import__("sys").modules.get("ppm_render") is not None).values())


def test_a_killed_workers_share_runs_again(ppm_core, still, cluster, tmp_path):
    # Shares of 6 passes: kill the worker running the first one while it runs. (Adaptive eye sampling
    # starts at a renderer's 8th pass, which shares of 6 never reach: off, for the single render to match.)
    still = dataclasses.replace(still, settings={**still.settings, "adaptive_samples": 1})
    passes, count = 24, 4
    futures = submit_shares(cluster, still, passes, count, threads=1)
    deadline = time.time() + 60
    busy = {}
    while time.time() < deadline and not busy:
        busy = {w: keys for w, keys in cluster.processing().items() if keys}
        time.sleep(0.05)
    assert busy, "no share started"
    victim = next(iter(busy))
    pid = cluster.run(os.getpid, workers=[victim])[victim]
    os.kill(pid, signal.SIGKILL)
    lines = []
    merge = ProgressiveMerge(str(tmp_path / "killed.exr"), count, 1e9, lines.append)
    merge.collect(futures)
    assert merge.finish()
    assert merge.merged.passes == passes, lines
    single = single_render(still, passes)
    np.testing.assert_allclose(merge.merged.image(), single.image(), rtol=1e-5, atol=1e-6 * single.image().max())


def test_shares_stop_at_their_deadline(still, cluster, tmp_path):
    # A share of 100,000 passes with 3 s left stops there; its passes merge with a short share's.
    until = time.time() + 3.0
    futures = submit_shares(cluster, still, 2, 1, threads=1, until=until)
    futures += submit_shares(cluster, still, 100_000, 1, threads=1, until=until, first_pass=2)
    lines = []
    merge = ProgressiveMerge(str(tmp_path / "late.exr"), 2, 1e9, lines.append)
    merge.collect(futures, deadline=30.0)
    assert time.time() < until + 15.0
    assert merge.finish() and merge.merged.ranges[0] == (0, 2)
    late = merge.merged.ranges[1]
    assert late[0] == 2 and 1 <= late[1] < 100_000


def test_shares_not_back_by_the_deadline_are_left_out(still, cluster, tmp_path):
    # A share with no deadline of its own that outlasts the client's (a worker lost from view):
    # cancelled, and the image holds the others. Last in the module: its worker stays busy.
    futures = submit_shares(cluster, still, 2, 1, threads=1)
    futures += submit_shares(cluster, still, 100_000, 1, threads=1, first_pass=2)
    lines = []
    merge = ProgressiveMerge(str(tmp_path / "lost.exr"), 2, 1e9, lines.append)
    start = time.perf_counter()
    merge.collect(futures, deadline=3.0)
    assert time.perf_counter() - start < 10.0
    assert merge.finish() and merge.merged.passes == 2
    assert any("not back by the deadline" in line for line in lines)
    assert futures[-1].status == "cancelled"


def cli_environment():
    """This process's environment with the add-on on PYTHONPATH (not all of sys.path: bpy adds
    Blender's own script folders, whose bpy package would shadow the module)."""
    paths = [os.path.join(ROOT, "addon"), *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(paths)}


def test_the_command_line_renders_a_still(tmp_path):
    output = tmp_path / "still.exr"
    scene = os.path.join(ROOT, "blend_scenes", "cornell_3spheres.blend")
    run = subprocess.run([sys.executable, "-m", "ppm_render.farm", scene, "--local-workers", "2", "--shares", "3",
                          "--passes", "6", "--resolution", "40", "30", "--output", str(output)],
                         capture_output=True, text=True, timeout=300, check=False,
                         env=cli_environment(), cwd=tmp_path)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "3/3 shares" in run.stdout and "wrote" in run.stdout
    pixels, header = read_exr_with_header(str(output))
    assert pixels.shape == (30, 40, 4) and header["ppm:passes"] == 6 and header["ppm:shares"] == 3
    assert 0.0 < header["ppm:error_relative"] < 1.0


def test_the_command_line_fails_readably(tmp_path):
    run = subprocess.run([sys.executable, "-m", "ppm_render.farm", str(tmp_path / "missing.blend"),
                          "--output", str(tmp_path / "x.exr")],
                         capture_output=True, text=True, timeout=300, check=False,
                         env=cli_environment(), cwd=tmp_path)
    assert run.returncode == 1 and "missing.blend' does not exist" in run.stderr


def test_share_settings_drop_what_does_not_split_into_shares():
    from ppm_render.farm.still_export import share_settings

    warnings = []
    out = share_settings({"hit_points": "fixed", "photon_guiding": True, "dof_mode": "post", "threads": 3,
                          "light_passes": True, "target_error": 0.02}, warnings.append)
    assert out["hit_points"] == "stochastic" and out["radius_schedule"] == "global"
    assert out["photon_guiding"] is False and out["dof_mode"] == "lens" and "threads" not in out
    assert out["light_passes"] is False and out["target_error"] == 0.0
    assert len(warnings) == 3 and any("guiding" in w for w in warnings)
    ppm_core = core.load()
    scene = ppm_core.Scene()
    scene.set_camera(np.eye(4), 8, 6)
    ppm_core.Renderer(scene, **out)  # the core takes them (it refuses guiding with shares)


def test_a_still_with_fog_renders_as_shares_that_merge_into_one_render(ppm_core):
    """fog_caustic.blend (a fog box, a glass ball, a spot light) at 32x24, exported as the farm exports it:
    its media are replayed on the worker, and two shares of 2 passes, merged, are one render's 4."""
    fog = bundled_still(ppm_core, "fog_caustic.blend", 32, 24, photons_per_pass=20_000)
    assert fog.warnings == [] and any(call[0] == "add_medium" for call in fog.calls)
    first, second = (shares.render_share(fog.calls, fog.settings, start, 2)[0] for start in (0, 2))
    merged = ppm_core.merge_shares([first, second])
    image = shares.render_share(fog.calls, fog.settings, 0, 4)[0].image()
    assert np.isfinite(image).all() and image[..., :3].mean() > 0.0
    np.testing.assert_allclose(merged.image(), image, rtol=1e-5, atol=1e-6 * image.max())
