"""The core's voxel grids' bytes against NanoVDB's for the same voxels (issue 48's goal: at most 1.5
times). NanoVDB's size is its nodes' (a float grid, NanoVDB 32.9.2, openvdb commit 568538e9, sizeof on
x86-64 with g++ 12, checked to the byte against grids its createNanoGrid built): 800 bytes of grid,
tree and root headers, 32 per root tile and per upper node 270,400 bytes (a 4096^3 region), per lower
node 33,856 (128^3), per leaf 2,144 (8^3); a constant 8^3 brick (an OpenVDB tile) is a value in its
lower node, no leaf. The core's: its bricks of 8^3 floats, a table of 16^3 places per block of 128^3
holding something and 4 bytes per block of the blocks' box (grid_info's bytes).

Grids: the smoke caches in tests/data (Blender 3.4's, read by the add-on's export/vdb.py), a
smoke-like domain of 256^3 (tools/grid_memory.py's blobs, dense as a smoke domain's), a ball's shell
10 voxels thick of radius 100 (sparse), and two voxels 4000 apart. One markdown table:

    PYTHONPATH=build/cp311-cp311-linux_x86_64 .venv/bin/python tools/nanovdb_memory.py
"""

import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from grid_memory import blobs  # noqa: E402

import ppm_core  # noqa: E402
from ppm_render.export import vdb  # noqa: E402

HEADERS, TILE, UPPER, LOWER, LEAF = 800, 32, 270_400, 33_856, 2_144


def nanovdb_bytes(info):
    """A NanoVDB float grid's bytes for the voxels of a core grid (grid_info): a leaf per stored brick
    (constant ones, tiles, are values in their lower node), a lower node per block, an upper node and
    a root tile per region."""
    return HEADERS + info["regions_4096"] * (TILE + UPPER) + info["blocks"] * LOWER + info["bricks"] * LEAF


def sparse(scene, name, values, origins, tile_origins=None, tile_values=None):
    return scene.add_sparse_grid(name, values, origins, np.eye(4), constant_origins=tile_origins,
                                 constant_values=tile_values)


def shell(radius=100, thickness=10):
    """The bricks of a ball's shell: voxels at distance radius - thickness .. radius from the origin."""
    edge = np.arange(-8 * (radius // 8 + 1), radius + 8, 8)
    bricks = np.stack(np.meshgrid(edge, edge, edge, indexing="ij"), axis=-1).reshape(-1, 3)
    local = np.stack(np.meshgrid(np.arange(8), np.arange(8), np.arange(8), indexing="ij"), axis=-1).reshape(-1, 3)
    origins, values = [], []
    for origin in bricks:
        r = np.linalg.norm(origin + local, axis=1)
        inside = (r >= radius - thickness) & (r < radius)
        if inside.any():
            origins.append(origin)
            values.append(inside.astype(np.float32))  # z fastest: local's last axis
    return np.array(origins, np.int32), np.array(values, np.float32)


def grids():
    """(what, scene, grid index, constant bricks) of each grid measured."""
    out = []
    for file in ("smoke_zip.vdb", "smoke_blosc_half.vdb"):
        for name, grid in sorted(vdb.read(os.path.join(ROOT, "tests", "data", file),
                                          blosc=ppm_core.blosc_decompress).items()):
            if grid.channels != 1:
                continue
            scene = ppm_core.Scene()
            tiles, tile_values = grid.constant_bricks()
            origins = grid.origins if grid.origins is not None else np.zeros((0, 3), np.int32)
            values = grid.values[..., 0] if grid.values is not None else np.zeros((0, 512), np.float32)
            index = sparse(scene, name, values, origins, tiles if len(tiles) else None,
                           tile_values[:, 0] if len(tiles) else None)
            out.append((f"{file} {name}", scene, index, len(tiles)))
    scene = ppm_core.Scene()
    out.append(("smoke-like domain 256^3 (dense)", scene, scene.add_grid("density", blobs(256)), 0))
    scene = ppm_core.Scene()
    origins, values = shell()
    out.append(("a ball's shell, radius 100, 10 thick", scene, sparse(scene, "shell", values, origins), 0))
    scene = ppm_core.Scene()
    two = np.zeros((2, 512), np.float32)
    two[0, 5] = two[1, 7] = 1.0
    out.append(("two voxels 4000 apart", scene, sparse(scene, "two", two, np.array([[0, 0, 0], [-4000, 4000, 4000]],
                                                                                   np.int32)), 0))
    return out


def main():
    print("| grid | bricks | core bytes | NanoVDB bytes | core / NanoVDB |")
    print("|---|---|---|---|---|")
    for what, scene, index, constants in grids():
        info = scene.grid_info(index)
        nano = nanovdb_bytes(info)
        print(f"| {what} | {info['bricks']} (+{constants} constant) | {info['bytes']:,} | {nano:,} | "
              f"{info['bytes'] / nano:.2f} |")


if __name__ == "__main__":
    main()
