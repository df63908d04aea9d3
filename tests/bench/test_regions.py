"""The image regions the accuracy benchmarks score (bench/harness/regions.py), on the bundled volumetric
caustic: its fog box is seen through, so the glass ball, the floor's caustic and the beam through the
fog are told apart; and a setting's path may name an item of a collection."""

from __future__ import annotations

import os
import sys

import numpy as np

BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "bench")
sys.path.insert(0, BENCH)
from harness import addon_route, regions  # noqa: E402

W, H = 64, 48


def test_fog_caustic_regions_see_through_the_fog_box():
    """Every camera ray meets the fog box's front first; seen as a surface it left one region, walls."""
    masks = regions.region_masks("fog_caustic", np.zeros((H, W, 3)), W, H)
    assert {"glass", "caustic", "walls", "beam"} <= set(masks)
    glass, beam, caustic = masks["glass"], masks["beam"], masks["caustic"]
    assert not (beam & glass).any()
    rows, cols = np.nonzero(glass)
    beam_rows, beam_cols = np.nonzero(beam)
    # The beam leaves the ball downwards to the floor's caustic spot (rows top-down).
    assert beam_rows.mean() > rows.mean() and beam_rows.max() >= np.nonzero(caustic)[0].min() - 2
    assert 0.01 * W * H < beam.sum() < 0.25 * W * H


def test_a_setting_path_names_an_item_of_a_collection():
    scene = addon_route.open_scene("fog_caustic", W, H)
    addon_route.apply(scene, scene.cycles, {"objects.spot.data.shadow_soft_size": 0.3})
    assert abs(scene.objects["spot"].data.shadow_soft_size - 0.3) < 1e-6
