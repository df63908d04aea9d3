"""Smoke and fire simulation domains -> the core's voxel grids (Scene.add_grid).

A gas domain (a mesh with a Fluid modifier of type Domain, Gas) renders in Cycles as its mesh's
Volume shader, whose attributes density, color, flame, heat and temperature read the simulation's
grids at the current frame (intern/cycles/blender/volume.cpp, BlenderSmokeLoader): dense grids of
the domain's resolution (times the noise's upscale where Noise is on; heat never upscaled) over the
evaluated mesh's texture space, empty outside the cache's frame range. The add-on reads the same
arrays through Python (FluidDomainSettings.density_grid and the rest) and gives each object the
grids its materials read, by the fixed slots of GRID_NAMES (node programs' grid instructions, which
read a grid at the Object coordinate: each grid's to_index maps it through the texture space).
"""
from __future__ import annotations

import numpy as np

# Cycles' standard volume attributes a gas domain gives, in the slot order programs read them.
GRID_NAMES = ("density", "color", "flame", "heat", "temperature")
CHANNELS = {"color": 4}
NOT_UPSCALED = {"heat"}  # heat stays at the base resolution when Noise is on (as Cycles reads it)


def gas_domain(obj):
    """The FluidDomainSettings of `obj`'s Fluid modifier where it is a gas (smoke, fire) domain."""
    for modifier in getattr(obj, "modifiers", ()):
        if modifier.type == "FLUID" and getattr(modifier, "fluid_type", "") == "DOMAIN":
            settings = modifier.domain_settings
            return settings if settings is not None and settings.domain_type == "GAS" else None
    return None


def to_index(obj, shape):
    """The 4x4 matrix from `obj`'s object space to the index space of a grid of `shape` (nz, ny, nx, ...)
    over its texture space: Generated = (p - (location - size)) / (2 size), voxel i's centre at
    Generated (i + 0.5) / n (a texture space of size 0 along an axis is 1 there, as Blender's)."""
    data = getattr(obj, "data", None)
    location = np.array(tuple(getattr(data, "texspace_location", (0.0, 0.0, 0.0))), float)
    size = np.array(tuple(getattr(data, "texspace_size", (1.0, 1.0, 1.0))), float)
    size = np.where(size == 0.0, 1.0, size)
    counts = np.array(shape[:3][::-1], float)  # nx, ny, nz
    m = np.eye(4)
    m[:3, :3] = np.diag(counts / (2.0 * size))
    m[:3, 3] = -(location - size) * counts / (2.0 * size) - 0.5
    return m


def add_empty_grid(core_scene, name, channels):
    """A grid that reads 0 everywhere (one voxel of 0): for a grid that is there but holds no data, as
    Cycles renders it, or one the core refused."""
    return core_scene.add_grid(f"{name} (empty)", np.zeros((1, 1, 1, channels), dtype=np.float32))


class GridNames:
    """The grid names an export's materials read, each a slot of the objects' grids (GRID_NAMES first,
    then any other name an Attribute node or attribute socket asks for: a Volume object's file may
    hold grids of any name, "Cd" or "vel")."""

    def __init__(self):
        self.names = list(GRID_NAMES)

    def slot(self, name):
        if name not in self.names:
            self.names.append(name)
        return self.names.index(name)


def _read_array(prop, count):
    values = np.empty(count, dtype=np.float32)
    try:
        prop.foreach_get(values)  # (Blender's property arrays: no Python float per voxel)
    except (AttributeError, TypeError, RuntimeError):
        values[:] = np.asarray(prop[:], dtype=np.float32)
    return values


def read_grid(domain, name, frame):
    """Grid `name` of `domain` at `frame` as (nz, ny, nx[, channels]) float32, a single zero voxel
    outside the cache's frame range (Cycles' empty grid), or None where the domain holds no data of
    the expected size (not simulated or baked to this frame)."""
    channels = CHANNELS.get(name, 1)
    if not domain.cache_frame_start <= frame <= domain.cache_frame_end:
        return np.zeros((1, 1, 1, channels) if channels > 1 else (1, 1, 1), dtype=np.float32)
    nx, ny, nz = (int(n) for n in domain.domain_resolution)
    scale = int(domain.noise_scale) if domain.use_noise and name not in NOT_UPSCALED else 1
    nx, ny, nz = nx * scale, ny * scale, nz * scale
    prop = getattr(domain, f"{name}_grid")
    count = nx * ny * nz * channels
    if count == 0 or len(prop) != count:
        return None
    shape = (nz, ny, nx, channels) if channels > 1 else (nz, ny, nx)
    return _read_array(prop, count).reshape(shape)


class SmokeGrids:
    """Adds each domain's grids to the core once (instances of a domain share them)."""

    def __init__(self, core_scene, frame, warn, stochastic=False):
        self.scene, self.frame, self.warn, self.stochastic = core_scene, frame, warn, stochastic
        self.added = {}  # (domain object name, grid name) -> grid index, or -1

    def indices(self, obj, names, table):
        """add_grid indices by slot of `table` (GridNames) for object `obj` (a gas domain) and the grid
        `names` its materials read; -1 where it is not read or a domain has no such grid. A domain
        without simulation data at this frame reads 0 there, as in Cycles (warned once)."""
        domain = gas_domain(obj)
        out = [-1] * len(table.names)
        if domain is None:
            return out
        for name in names:
            if name not in GRID_NAMES:
                continue
            key = (obj.name, name)
            if key not in self.added:
                self.added[key] = self.add(obj, domain, name)
            out[table.slot(name)] = self.added[key]
        return out

    def add(self, obj, domain, name):
        """The grid's index; an empty one (it reads 0) where the domain has no data or the core refuses it."""
        values = read_grid(domain, name, self.frame)
        if values is None:
            self.warn(f"smoke domain '{obj.name}': no simulation data of its '{name}' at frame {self.frame} "
                      "(bake the simulation, or play it to this frame); it renders empty, as in Cycles")
            return add_empty_grid(self.scene, f"{obj.name}/{name}", CHANNELS.get(name, 1))
        try:
            return self.scene.add_grid(f"{obj.name}/{name}", values, to_index=to_index(obj, values.shape),
                                       stochastic=self.stochastic)
        except ValueError as error:
            self.warn(f"smoke domain '{obj.name}': its '{name}' is not rendered ({error}); it reads 0")
            return add_empty_grid(self.scene, f"{obj.name}/{name}", CHANNELS.get(name, 1))
