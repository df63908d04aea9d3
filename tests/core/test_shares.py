"""Sharded stills (engine/ppm/share.h): passes of the global radius schedule rendered by different
renderers, each from its own first_pass, merge into the image and error estimate of one renderer
that rendered them all."""

import pickle

import numpy as np
import pytest

import core_scenes
import ppm_core

GLOBAL = dict(hit_points="stochastic", radius_schedule="global", photons_per_pass=5_000, threads=2, seed=11)


def share_of(scene, first_pass, passes, **settings):
    renderer = ppm_core.Renderer(scene, first_pass=first_pass, **{**GLOBAL, **settings})
    renderer.run(passes=passes)
    return renderer.share()


@pytest.fixture(scope="module")
def box():
    return core_scenes.cornell_3spheres(40, 30)


@pytest.fixture(scope="module")
def whole(box):
    """One renderer's 9 passes."""
    renderer = ppm_core.Renderer(box, **GLOBAL)
    renderer.run(passes=9)
    return renderer


def test_merged_shares_are_the_single_render(box, whole):
    # Passes 0-2, 3-7 and 8, merged in any order: the image and the error estimate of passes 0-8.
    parts = [share_of(box, 8, 1), share_of(box, 0, 3), share_of(box, 3, 5)]
    merged = ppm_core.merge_shares(parts)
    assert merged.passes == 9 and merged.ranges == [(0, 3), (3, 5), (8, 1)]
    image = whole.image()
    np.testing.assert_allclose(merged.image(), image, rtol=1e-5, atol=1e-6 * image.max())
    expected = whole.stats()["error"]
    for key, value in merged.error_stats().items():
        assert value == pytest.approx(expected[key], rel=1e-4), key
    error = merged.error()
    np.testing.assert_allclose(error["noise"], whole.error()["noise"], rtol=1e-3, atol=1e-6)
    np.testing.assert_allclose(ppm_core.merge_shares(parts[::-1]).image(), merged.image(), rtol=1e-6, atol=1e-7)


def test_a_share_is_the_renderers_image_and_error(box, whole):
    share = whole.share()
    assert share.ranges == [(0, 9)] and share.seed == GLOBAL["seed"]
    np.testing.assert_array_equal(share.image(), whole.image())
    np.testing.assert_array_equal(share.error()["bias"], whole.error()["bias"])


def test_shares_travel_as_plain_data(box):
    share = share_of(box, 4, 2, light_passes=True)
    back = pickle.loads(pickle.dumps(share))
    assert back.ranges == share.ranges and back.passes == 2
    np.testing.assert_array_equal(back.image(), share.image())
    for name in ("Emit", "Env"):
        np.testing.assert_array_equal(back.light_passes()[name], share.light_passes()[name])
    data = share.to_dict()
    assert set(data) >= {"image", "moments", "ranges", "seed", "alpha", "photons_per_pass", "light_passes"}
    data["moments"] = data["moments"][:, :-1]
    with pytest.raises(ValueError, match="moments"):
        ppm_core.Share.from_dict(data)


def test_light_passes_merge(box):
    merged = ppm_core.merge_shares([share_of(box, 0, 2, light_passes=True), share_of(box, 2, 2, light_passes=True)])
    renderer = ppm_core.Renderer(box, light_passes=True, **GLOBAL)
    renderer.run(passes=4)
    for name, values in renderer.light_passes().items():
        np.testing.assert_allclose(merged.light_passes()[name], values, rtol=1e-5, atol=1e-6)


def test_shares_of_different_stills_are_refused(box):
    base = share_of(box, 0, 1)
    with pytest.raises(ValueError, match="pass 0 is in both"):
        ppm_core.merge_shares([base, share_of(box, 0, 2)])
    with pytest.raises(ValueError, match="seeds differ"):
        ppm_core.merge_shares([base, share_of(box, 1, 1, seed=12)])
    with pytest.raises(ValueError, match="alpha"):
        ppm_core.merge_shares([base, share_of(box, 1, 1, alpha=0.5)])
    with pytest.raises(ValueError, match="photons_per_pass"):
        ppm_core.merge_shares([base, share_of(box, 1, 1, photons_per_pass=4_000)])
    with pytest.raises(ValueError, match="sizes differ"):
        ppm_core.merge_shares([base, share_of(core_scenes.cornell_3spheres(20, 30), 1, 1)])
    with pytest.raises(ValueError, match="no shares"):
        ppm_core.merge_shares([])


def test_settings_that_cannot_share_are_refused(box):
    with pytest.raises(ValueError, match="needs hit_points 'stochastic'"):
        ppm_core.Renderer(box, radius_schedule="global", hit_points="fixed")
    with pytest.raises(ValueError, match="needs radius_schedule 'global'"):
        ppm_core.Renderer(box, hit_points="stochastic", first_pass=3)
    progressive = ppm_core.Renderer(box, hit_points="stochastic", photons_per_pass=1000)
    progressive.run(passes=1)
    with pytest.raises(RuntimeError, match="radius_schedule='global'"):
        progressive.share()
    fresh = ppm_core.Renderer(box, **GLOBAL)
    with pytest.raises(RuntimeError, match="no pass"):
        fresh.share()


def test_a_paused_pass_is_not_shared():
    scene = core_scenes.cornell_3spheres(64, 2048)  # several bands a pass
    renderer = ppm_core.Renderer(scene, **GLOBAL)
    renderer.run(passes=1)
    renderer.run(passes=1, pause_after=1e-9)
    assert 0.0 < renderer.stats()["pass_done"] < 1.0
    with pytest.raises(RuntimeError, match="in progress"):
        renderer.share()
    renderer.run(passes=1)
    assert renderer.share().ranges == [(0, 2)]


@pytest.mark.accuracy
def test_global_schedule_converges_on_the_closed_sphere():
    # Known answer (test_analytic.py): 3 shares of 20 passes, merged, within 1% on average.
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    settings = dict(photons_per_pass=20_000, direct_light="photons")
    merged = ppm_core.merge_shares([share_of(scene, k * 20, 20, **settings) for k in range(3)])
    expected = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)
    assert merged.image()[..., :3].mean() == pytest.approx(expected, rel=0.01)
