"""Volume objects (OpenVDB grids from .vdb files) -> a closed box around their grids that carries their
material's medium, and the grids that material reads (vdb.py; Scene.add_sparse_grid).

Cycles renders a Volume object as its material's Volume inside a mesh it builds around the grids'
active voxels, the attributes density, color, flame, heat and temperature reading the grids of those
names, in the object's space through each grid's transform (intern/cycles/blender/volume.cpp,
BlenderVolumeLoader). Here the mesh is the box of every grid's voxels (one voxel beyond, where the
trilinear lookup fades to 0), which holds the same medium wherever the material's density comes from
a grid. The file is the one Blender loads for the frame (VolumeGrids.frame_filepath).
"""
from __future__ import annotations

import os

import numpy as np

from . import smoke, vdb
from .mesh import MeshData

# A box's faces over its corners (_corners' order), counter-clockwise seen from outside.
FACES = ((0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5))


def file_of(obj):
    """The .vdb file Blender loads for `obj` (a Volume object) at this frame, or (None, why not)."""
    volume = obj.data
    grids = volume.grids
    try:
        if not grids.is_loaded:
            grids.load()
    except (RuntimeError, TypeError):
        pass
    path = getattr(grids, "frame_filepath", "") or ""
    if not path:
        error = getattr(grids, "error_message", "")
        why = f"its file cannot be loaded ({error})" if error else \
            "it has no .vdb file (grids made by modifiers or Geometry Nodes are not rendered yet)"
        return None, why
    import bpy  # (the add-on's modules import bpy only where Blender is there)

    return bpy.path.abspath(path, library=getattr(volume, "library", None)), None


def density_scale(item):
    """What Cycles multiplies a Volume object's volume closures by: with its Volume's space Object (the
    default), 1 / |M (1, 1, 1) / sqrt 3| for its matrix M, so that its density follows its scale
    (intern/cycles/scene/object.cpp, object_volume_density); 1 in World space."""
    render = getattr(item.obj.data, "render", None)
    if getattr(render, "space", "OBJECT") != "OBJECT":
        return 1.0
    length = float(np.linalg.norm(item.matrix[:3, :3] @ (np.ones(3) / np.sqrt(3.0))))
    return 1.0 / length if length > 0.0 and np.isfinite(length) else 1.0


def _corners(lo, hi):
    """A box's 8 corners, corner i at the high end along axis k where bit k of i is set."""
    return np.array([[(hi if (i >> k) & 1 else lo)[k] for k in range(3)] for i in range(8)], dtype=float)


def box_mesh(grids):
    """MeshData of the closed box (object space) around every grid's bricks, one voxel beyond; None when
    the grids hold no voxel."""
    corners = []
    for grid in grids.values():
        box = grid.index_box()
        if box is None:
            continue
        extremes = _corners(box[0] - 1.0, box[1].astype(float))
        corners.append((np.c_[extremes, np.ones(8)] @ grid.index_to_object.T)[:, :3])
    if not corners:
        return None
    every = np.concatenate(corners)
    lo, hi = every.min(axis=0), every.max(axis=0)  # their union's box in object space
    positions = _corners(lo, hi)
    triangles = np.array([t for a, b, c, d in FACES for t in ((a, b, c), (a, c, d))], dtype=np.int32)
    normals = np.repeat(_face_normals(positions, triangles)[:, None, :], 3, axis=1)
    return MeshData(positions, triangles, normals, None, np.zeros(len(triangles), dtype=np.int32))


def _face_normals(positions, triangles):
    p = positions[triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)


class VolumeObjects:
    """Reads each Volume object's file once and adds the grids its materials read to the core once."""

    def __init__(self, core_scene, warn, blosc, stochastic=False):
        self.scene, self.warn, self.blosc, self.stochastic = core_scene, warn, blosc, stochastic
        self.files = {}  # path -> {name: Grid}, or the VdbError it cannot be read for
        self.paths = {}  # object name -> the path grids() found for it
        self.added = {}  # (path, name) -> grid index

    def grids(self, obj):
        """({name: vdb.Grid} of `obj`'s file, None) or (None, why it is left out)."""
        path, why = file_of(obj)
        if path is None:
            return None, why
        self.paths[obj.name] = path
        if path not in self.files:
            try:
                self.files[path] = vdb.read(path, blosc=self.blosc)
            except vdb.VdbError as error:
                self.files[path] = error
        grids = self.files[path]
        if isinstance(grids, vdb.VdbError):
            return None, f"its file '{os.path.basename(path)}' {grids}"
        if not grids:
            return None, f"its file '{os.path.basename(path)}' holds no float or vector grid"
        return grids, None

    def indices(self, obj, names, table):
        """add_sparse_grid indices by slot of `table` (smoke.GridNames) of the grids `names` that `obj`'s
        file (as grids() found it) has; -1 elsewhere (a Principled Volume's attribute then multiplies by
        1, an Attribute node reads 0, as in Cycles)."""
        out = [-1] * len(table.names)
        path = self.paths.get(obj.name)
        grids = self.files.get(path)
        grids = grids if isinstance(grids, dict) else {}
        for name in names:
            if name not in grids:
                continue
            if (path, name) not in self.added:
                self.added[(path, name)] = self.add(obj, grids[name])
            out[table.slot(name)] = self.added[(path, name)]
        return out

    def add(self, obj, grid):
        if np.any(grid.background):
            self.warn(f"Volume object '{obj.name}': grid '{grid.name}' has a background of {grid.background.tolist()}; "
                      "read as 0 outside its voxels")
        if grid.skipped_tiles:
            self.warn(f"Volume object '{obj.name}': grid '{grid.name}' has {grid.skipped_tiles} constant regions too "
                      "large to hold; left out")
        origins, values = grid.constant_bricks()
        try:
            return self.scene.add_sparse_grid(f"{obj.name}/{grid.name}", grid.values, grid.origins,
                                              np.linalg.inv(grid.index_to_object), origins, values,
                                              stochastic=self.stochastic)
        except (ValueError, np.linalg.LinAlgError) as error:
            self.warn(f"Volume object '{obj.name}': grid '{grid.name}' is not rendered ({error}); it reads 0")
            return smoke.add_empty_grid(self.scene, f"{obj.name}/{grid.name}", grid.channels)
