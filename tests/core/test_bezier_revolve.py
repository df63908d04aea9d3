"""The Bezier revolve primitive through ppm_core: hits agree with a finely
tessellated mesh of the same surface, bad profiles raise clear errors, and a
glass vase renders with finite, plausible values."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core

CHAIN = [(0.0, 0.0), (0.4, 0.0), (0.6, 0.1), (0.6, 0.3), (0.6, 0.5), (0.2, 0.5), (0.25, 0.8),
         (0.3, 1.0), (0.5, 1.0), (0.45, 1.2)]  # three cubic segments, non-monotone radius


def transform(scale, angle, offset):
    m = np.eye(4)
    c, s = math.cos(angle), math.sin(angle)
    m[:3, :3] = np.array([[1, 0, 0], [0, c, -s], [0, s, c]]) @ np.diag(scale)
    m[:3, 3] = offset
    return m


def rays_towards(lo, hi, n, rng):
    """Rays from a sphere around the box [lo, hi] towards random points inside it."""
    center, half = (lo + hi) / 2, (hi - lo) / 2
    origins = center + 3 * np.linalg.norm(half) * _unit(rng.normal(size=(n, 3)))
    targets = center + half * (rng.random((n, 3)) * 2 - 1)
    return origins, targets - origins


def _unit(v):
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.mark.accuracy
@pytest.mark.parametrize("points,kind", [(core_scenes.VASE_PROFILE, "single"), (CHAIN, "chain")])
@pytest.mark.parametrize("scale,angle,offset", [((1, 1, 1), 0.0, (0, 0, 0)),
                                                ((1e-3, 2e-3, 1e-3), 0.7, (5.0, -3.0, 1.0)),
                                                ((300.0, 300.0, 500.0), -1.1, (1e4, 0, 0))])
def test_revolve_agrees_with_tessellated_mesh(points, kind, scale, angle, offset):
    m = transform(scale, angle, offset)
    exact = ppm_core.Scene()
    exact.add_material("m")
    exact.add_bezier_revolve("vase", points, kind=kind, matrix=m)
    mesh = ppm_core.Scene()
    mesh.add_material("m")
    pos, tris = core_scenes.tessellate_revolve(points, kind, m, profile_steps=600, angle_steps=1200)
    mesh.add_mesh("tessellated", pos, tris)
    rng = np.random.default_rng(1)
    lo, hi = pos.min(axis=0), pos.max(axis=0)
    size = float(np.linalg.norm(hi - lo))
    o, d = rays_towards(lo, hi, 4000, rng)
    a, b = exact.intersect(o, d), mesh.intersect(o, d)
    both = np.isfinite(a["t"]) & np.isfinite(b["t"])
    disagree = np.isfinite(a["t"]) != np.isfinite(b["t"])
    assert both.sum() > 1000
    # Hit/miss may differ only at silhouettes, within the tessellation's sagitta.
    assert disagree.mean() < 0.005
    # Distances agree to the tessellation error (chord sagitta ~ 1e-5 of the size here).
    err = np.abs(a["t"][both] - b["t"][both]) / size
    assert np.quantile(err, 0.99) < 2e-4 and np.median(err) < 2e-5
    # Normals agree where the surface is not seen edge-on.
    cos = np.abs(np.sum(a["normal"][both] * b["normal"][both], axis=1))
    assert np.quantile(cos, 0.05) > 0.99
    assert np.all(np.isfinite(a["normal"][np.isfinite(a["t"])]))


@pytest.mark.parametrize(
    "points,kind,message",
    [
        ([(0.0, 0.0)], "single", "at least 2 points"),
        ([(0.0, 0.0), (math.nan, 1.0)], "single", "point 1"),
        ([(0.1 * i, i) for i in range(10)], "single", "degree"),
        ([(0, 0), (1, 0), (1, 1), (0, 1), (0, 2)], "chain", "3k+1"),
        ([(1.0, 1.0)] * 4, "single", "identical"),
    ],
)
def test_bad_profiles_raise(points, kind, message):
    scene = ppm_core.Scene()
    scene.add_material("m")
    with pytest.raises(ValueError) as err:
        scene.add_bezier_revolve("vase", points, kind=kind)
    assert "bezier revolve 'vase'" in str(err.value) and message in str(err.value)


def test_singular_matrix_raises():
    scene = ppm_core.Scene()
    scene.add_material("m")
    with pytest.raises(ValueError, match="singular"):
        scene.add_bezier_revolve("vase", core_scenes.VASE_PROFILE, matrix=np.diag([1.0, 0.0, 1.0, 1.0]))


def test_glass_vase_renders_with_a_caustic():
    r = ppm_core.Renderer(core_scenes.bezier_vase(96, 72), photons_per_pass=100_000, threads=2)
    r.run(passes=8)
    img = r.image()[..., :3]
    assert np.isfinite(img).all() and img.min() >= 0.0
    assert 0.01 < img.mean() < 10.0
    assert r.stats()["photons_deposited"] > 0
