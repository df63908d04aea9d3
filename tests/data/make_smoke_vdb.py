"""Writes tests/data/smoke_zip.vdb and smoke_blosc_half.vdb: Quick Smoke (fire and smoke) at resolution 16,
no noise, baked by this Blender to frame 12 with a ZIP float and a Blosc half OpenVDB cache (the
cache's data file: density, temperature, flame, shadow and velocity grids), and the density grid
Blender holds at that frame (smoke_density.npy, (z, y, x)). Made with Debian's Blender 3.4.1:

    blender -b --factory-startup -P tests/data/make_smoke_vdb.py -- tests/data
"""
import os
import shutil
import sys
import tempfile

import bpy
import numpy as np

FRAME = 12


def main(out):
    bpy.ops.wm.read_factory_settings(use_empty=False)
    cube = bpy.data.objects["Cube"]
    cube.scale = (0.3, 0.3, 0.3)
    bpy.context.view_layer.objects.active = cube
    cube.select_set(True)
    bpy.ops.object.quick_smoke(style="BOTH")
    domain = bpy.data.objects["Smoke Domain"]
    settings = domain.modifiers["Fluid"].domain_settings
    settings.resolution_max, settings.use_noise = 16, False
    scene = bpy.context.scene
    for compression, depth, name in (("ZIP", "32", "smoke_zip.vdb"), ("BLOSC", "16", "smoke_blosc_half.vdb")):
        cache = os.path.join(tempfile.gettempdir(), f"ppm_smoke_vdb_{compression}")
        shutil.rmtree(cache, ignore_errors=True)
        settings.cache_directory, settings.cache_type, settings.cache_data_format = cache, "ALL", "OPENVDB"
        settings.openvdb_cache_compress_type, settings.openvdb_data_depth = compression, depth
        scene.frame_end = settings.cache_frame_end = FRAME
        bpy.ops.fluid.bake_all()
        scene.frame_set(FRAME)
        shutil.copy(os.path.join(cache, "data", f"fluid_data_{FRAME:04d}.vdb"), os.path.join(out, name))
        if compression == "ZIP":
            evaluated = domain.evaluated_get(bpy.context.evaluated_depsgraph_get()).modifiers["Fluid"]
            res = tuple(evaluated.domain_settings.domain_resolution)
            density = np.array(evaluated.domain_settings.density_grid, np.float32).reshape(res[::-1])
            np.save(os.path.join(out, "smoke_density.npy"), density)


if __name__ == "__main__":
    main(sys.argv[-1])
