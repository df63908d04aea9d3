"""Smoke and fire domains' grids as export/smoke.py reads them, on stand-ins for FluidDomainSettings (the
bpy modules cannot simulate, and abort at exit once a fluid domain exists): the layout (x fastest), the
noise's upscale (heat excepted), the cache's frame range, a domain without data (warned, empty), and a
gas domain told apart from a liquid one. Rendered against Cycles: tests/blenders/media_compare.py
(smoke_sim, fire_sim, in the blender binary)."""

from types import SimpleNamespace

import numpy as np
import pytest

import ppm_core
from ppm_render.export import smoke


def domain(nx=4, ny=3, nz=2, noise=1, frames=(1, 250), **grids):
    """A FluidDomainSettings stand-in: `grids` by name as flat lists, none given: empty."""
    settings = SimpleNamespace(domain_type="GAS", domain_resolution=(nx, ny, nz), use_noise=noise > 1,
                               noise_scale=noise, cache_frame_start=frames[0], cache_frame_end=frames[1])
    for name in smoke.GRID_NAMES:
        setattr(settings, f"{name}_grid", grids.get(name, []))
    return settings


def test_a_grid_is_laid_out_x_fastest():
    values = list(range(4 * 3 * 2))
    grid = smoke.read_grid(domain(density=values), "density", 1)
    assert grid.shape == (2, 3, 4) and grid.dtype == np.float32
    assert grid[1, 2, 3] == 3 + 4 * (2 + 3 * 1)


def test_noise_upscales_every_grid_but_heat_and_colour_has_four_channels():
    settings = domain(nx=2, ny=2, nz=2, noise=2, density=[0.5] * 64, heat=[1.0] * 8, color=[0.2] * 256)
    assert smoke.read_grid(settings, "density", 1).shape == (4, 4, 4)
    assert smoke.read_grid(settings, "heat", 1).shape == (2, 2, 2)
    assert smoke.read_grid(settings, "color", 1).shape == (4, 4, 4, 4)


def test_outside_the_cache_frames_a_grid_is_empty_as_in_cycles():
    grid = smoke.read_grid(domain(frames=(10, 20), density=[1.0] * 24), "density", 30)
    assert grid.shape == (1, 1, 1) and grid.max() == 0.0


def test_a_domain_without_data_reads_nothing_warned_once_and_renders_empty():
    obj = SimpleNamespace(name="Smoke Domain", modifiers=[
        SimpleNamespace(type="FLUID", fluid_type="DOMAIN", domain_settings=domain(density=[1.0] * 5))])
    assert smoke.read_grid(obj.modifiers[0].domain_settings, "density", 1) is None  # 5 values, not 24
    warnings = []
    scene = ppm_core.Scene()
    grids, table = smoke.SmokeGrids(scene, 1, warnings.append), smoke.GridNames()
    first = grids.indices(obj, ["density"], table)
    assert grids.indices(obj, ["density"], table) == first  # added once
    assert first[table.slot("density")] >= 0 and first[table.slot("flame")] == -1
    assert grids.indices(obj, ["Cd"], table) == [-1] * len(table.names)  # not a domain's grid
    assert scene.grid_info(first[0])["max_value"] == 0.0
    assert len(warnings) == 1 and "Smoke Domain" in warnings[0] and "no simulation data" in warnings[0]


@pytest.mark.parametrize("kind", ["GAS", "LIQUID"])
def test_only_a_gas_domain_gives_grids(kind):
    settings = domain()
    settings.domain_type = kind
    obj = SimpleNamespace(modifiers=[SimpleNamespace(type="FLUID", fluid_type="DOMAIN", domain_settings=settings)])
    assert (smoke.gas_domain(obj) is settings) == (kind == "GAS")
    assert smoke.gas_domain(SimpleNamespace(modifiers=[])) is None
