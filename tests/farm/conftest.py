"""The farm's tests: a bundled .blend exported once with bpy (Blender 5.0 as a module), rendered in
shares on a dask LocalCluster of worker processes."""

import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy  # noqa: E402  (installed by make setup; a missing bpy must fail, not skip)

import ppm_render  # noqa: E402
from ppm_render import core  # noqa: E402
from ppm_render.farm.still_export import export_still  # noqa: E402


@pytest.fixture(scope="session")
def ppm_core():
    return core.load()


@pytest.fixture(scope="session")
def still(ppm_core):
    """cornell_diffuse.blend at 48x36, exported as the farm exports it; its warnings in `warnings`."""
    ppm_render.register()
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "blend_scenes", "cornell_diffuse.blend"))
        render = bpy.context.scene.render
        render.resolution_x, render.resolution_y, render.resolution_percentage = 48, 36, 100
        bpy.context.scene.ppm.photons_per_pass = 20_000
        warnings = []
        exported = export_still(bpy, ppm_core, warnings.append)
        exported.warnings = warnings
        yield exported
    finally:
        ppm_render.unregister()  # bpy 4.2 crashes and 4.5 hangs at exit while a script's classes are registered


@pytest.fixture(scope="module")
def cluster():
    """Two worker processes with one thread each, as a farm's machines (no dashboard)."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as local, \
            Client(local) as client:
        yield client
