"""Random hostile scenes (fuzz_scenes.py) render: no exception, no crash, no refused frame."""

import pytest

import fuzz_scenes
from conftest import bpy

SEEDS = range(60)


@pytest.mark.parametrize("seed", SEEDS)
def test_a_random_hostile_scene_renders(seed):
    fuzz_scenes.build(seed)
    bpy.ops.render.render()  # raises RuntimeError with the engine's message if the frame fails
