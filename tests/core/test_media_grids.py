"""Media whose density is a voxel grid (a smoke domain's, Scene.add_grid) through ppm_core: a ramp
of voxels transmits exp(-its trilinear integral), one dense voxel between the points the core would
sample for a bound is not missed, and bad grids are refused with a message. The grid's lookup itself
is tested in voxel_grid_test.cpp."""

from __future__ import annotations

import numpy as np
import pytest
from test_media import box, emitter_seen_through
from test_node_program import op

import ppm_core

SIGMA_A = np.array([0.2, 0.5, 1.0])
DEPTH = 1.5  # the slab's thickness along y


def grid_density():
    """A program whose one output is the fac of the object's grid in slot 0 at its Generated."""
    return {"constants": [], "code": [op("coord", "generated", out=[1]),
                                      {"op": "grid", "in": [1], "out": [2, 3, 4], "data": 0}],
            "outputs": [3], "registers": 5}


def slab_of_grid(values, majorant_grids=True, majorants=None):
    """An absorbing slab 2 x DEPTH x 2 m about the origin whose texture space is its box, its density
    the grid `values` ((nz, ny, nx)), sigma_a SIGMA_A per unit density; an emitter of radiance 2 seen
    through it along y by rays that all cross it at Generated x = z = 0.5. Returns the pixels;
    `majorants` (a list) gets the scene's medium_majorants."""
    scene = ppm_core.Scene()
    scene.majorant_grids = majorant_grids
    grid = scene.add_grid("density", np.asarray(values, dtype=np.float32))
    scene.add_medium("smoke", program=grid_density(), terms=[{"sigma_a": tuple(SIGMA_A), "input": 0}])
    slab = scene.add_material("smoke", "diffuse", medium="smoke", surface=False)
    box(scene, "slab", (-1.0, -DEPTH / 2, -1.0), (1.0, DEPTH / 2, 1.0), slab, 0)
    scene.set_object_info(0, np.eye(4), texspace_location=(0, 0, 0), texspace_size=(1.0, DEPTH / 2, 1.0),
                          grids=[grid])
    pixels = emitter_seen_through(scene, panel_y=3, eye_y=-4, object_id=1, passes=400)
    if majorants is not None:
        majorants.extend(scene.medium_majorants)
    return pixels


def assert_transmits(pixels, optical_depth):
    mean, error = pixels.mean(axis=0), pixels.std(axis=0) / np.sqrt(len(pixels))
    expected = 2.0 * np.exp(-SIGMA_A * optical_depth)
    assert np.all(np.abs(mean - expected) < 4.0 * error + 1e-4), (mean, expected, error)


@pytest.mark.accuracy
def test_a_ramp_of_voxels_transmits_exp_minus_its_trilinear_integral():
    """Six voxels along y holding 0.5, 0.8 .. 2.0 (two across x and z, alike): between cell centres the
    density is linear, over the half cell at each face it fades to half the end voxel's value (a grid's
    outside is 0), so the optical depth is the trapezoids' sum plus 3/8 of each end voxel, in cells of
    DEPTH / 6. Within 4 standard errors of the pixels' mean; the voxels taken as their mean over the
    whole slab would read 1.6-7.8% darker."""
    ramp = 0.5 + 0.3 * np.arange(6)
    values = np.broadcast_to(ramp[None, :, None], (2, 6, 2))
    cells = np.sum((ramp[:-1] + ramp[1:]) / 2) + 0.375 * (ramp[0] + ramp[-1])
    assert_transmits(slab_of_grid(values), cells * DEPTH / 6)


@pytest.mark.accuracy
def test_one_dense_voxel_between_the_sampled_points_is_not_missed():
    """A 64^3 grid empty but for a 2 x 1 x 2 block of density 40 on the rays' path, at a row that a
    24^3 sampling of the box (what the core does for a density it cannot bound) does not reach: the
    tracker's majorant is the grid's largest value, so the block's optical depth, 40 DEPTH / 64 per
    unit sigma_a, is all there (missed, the slab would read as clear)."""
    values = np.zeros((64, 64, 64), dtype=np.float32)
    values[31:33, 2, 31:33] = 40.0
    assert_transmits(slab_of_grid(values), 40.0 * DEPTH / 64)


@pytest.mark.accuracy
def test_a_sparse_cloud_is_tracked_cell_by_cell_and_transmits_the_same():
    """A 64^3 grid empty but for a block of density 3 on the rays' path (16 voxels along y) and one
    voxel of 40 in a corner: the medium's majorant grid bounds the block's cells by 3 and the empty
    ones by 0 (not everywhere by the corner's 40), and the slab transmits exp(-16 x 3 DEPTH / 64) (15
    cells between the end voxels' centres, and half a cell of each end voxel fading to its empty
    neighbour) as with one majorant."""
    values = np.zeros((64, 64, 64), dtype=np.float32)
    values[28:36, 24:40, 28:36] = 3.0
    values[1, 62, 1] = 40.0
    depth = 16 * 3.0 * DEPTH / 64
    majorants = []
    assert_transmits(slab_of_grid(values, majorants=majorants), depth)
    (copy,) = majorants
    assert copy["majorant"] == pytest.approx(40.0 * SIGMA_A.max())
    assert copy["cells"] == (32, 24, 32)  # the box's 2 x DEPTH x 2 m
    assert copy["mean_cell"] < 0.01 * copy["majorant"]
    majorants = []
    assert_transmits(slab_of_grid(values, majorant_grids=False, majorants=majorants), depth)
    assert "cells" not in majorants[0]


def test_grids_that_cannot_be_one_are_refused_with_their_name():
    scene = ppm_core.Scene()
    with pytest.raises(ValueError, match="grid 'flat'.*shape"):
        scene.add_grid("flat", np.zeros((4, 4)))
    with pytest.raises(ValueError, match="grid 'pairs'.*1, 3 or 4 channels"):
        scene.add_grid("pairs", np.zeros((2, 2, 2, 2)))
    with pytest.raises(ValueError, match="grid 'empty'.*size"):
        scene.add_grid("empty", np.zeros((0, 2, 2)))
    with pytest.raises(ValueError, match="real numbers"):
        scene.add_grid("words", np.array([[["a"]]]))
    with pytest.raises(ValueError, match="object 0.*grid that does not exist"):
        scene.set_object_info(0, np.eye(4), grids=[3])


def test_values_that_are_not_finite_are_stored_as_zero_and_counted():
    scene = ppm_core.Scene()
    index = scene.add_grid("smoke", np.array([[[np.nan, 1.0, np.inf, -2.0]]]))
    info = scene.grid_info(index)
    assert info["not_finite"] == 2 and info["max_value"] == 1.0 and info["index_hi"] == (8, 8, 8)
