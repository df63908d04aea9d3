"""Streamed fixed hit points (engine/ppm/streamed_hit_points.h): made again band by band every pass
instead of kept, they are the same hit points, so the image is the kept hit points' one up to float
statistics, in 36 bytes a hit point and 20 a pixel (36 with the error estimate)."""

import numpy as np
import pytest

import core_scenes
import ppm_core

SIZE = (320, 240)  # at 4 eye samples a pixel, bands of 51 rows (RenderContext::band_rows): five


def cornell(storage, size=SIZE, aperture_radius=0.0, **settings):
    return ppm_core.Renderer(core_scenes.cornell_3spheres(*size, aperture_radius=aperture_radius),
                             photons_per_pass=20_000, threads=2, hit_points="fixed", hit_point_storage=storage,
                             **settings)


@pytest.mark.accuracy
@pytest.mark.parametrize("settings", [
    {},                                       # direct light sampled, glass chains, five bands
    {"direct_light": "photons"},
    {"samples_per_pixel": 1},
    {"grid": "hash"},
    {"gather": "hit_points"},                 # one band: the hit points are indexed
    {"light_path_limits": True, "diffuse_bounces": 1},  # each hit point's eye chain is made again too
    {"dof_mode": "post", "aperture_radius": 0.05},      # the depth buffer from the first eye pass
], ids=["default", "direct_photons", "spp1", "hash", "hit_point_index", "light_path_limits", "dof_post"])
def test_streamed_hit_points_find_the_kept_image(settings):
    kept, streamed = cornell("kept", **settings), cornell("streamed", **settings)
    for renderer in (kept, streamed):
        renderer.run(passes=4)
    a, b = kept.image(), streamed.image()
    ks, ss = kept.stats(), streamed.stats()
    assert ks["hit_point_storage"] == "kept" and ss["hit_point_storage"] == "streamed"
    assert ss["hit_points"] == ks["hit_points"] > SIZE[0] * SIZE[1] // 2
    assert ss["radii_widened"] == ks["radii_widened"] and ss["direct_samples"] == ks["direct_samples"]
    assert ss["initial_radius_mean"] == pytest.approx(ks["initial_radius_mean"], rel=1e-6)
    assert ss["radius_mean"] == pytest.approx(ks["radius_mean"], rel=1e-6)
    assert a[..., :3].mean() > 0.05
    assert not any("depth of field" in line for line in ss["skipped"]) or "dof_mode" not in settings
    assert np.abs(a - b).sum() <= 1e-6 * np.abs(a).sum()
    assert np.abs(a - b).max() <= 1e-4 * a[..., :3].max()


def test_streamed_hit_points_keep_36_bytes_a_hit_point_and_20_a_pixel():
    renderer = cornell("streamed", size=(640, 480))
    renderer.run(passes=1)
    stats = renderer.stats()
    memory, hit_points, pixels = stats["memory"], stats["hit_points"], 640 * 480
    assert memory["pixels"] == (20 + 16) * pixels + 4  # with the error estimate's 16 (error_estimate.h)
    band = 65536  # eye samples (RenderContext::kBandPixels): one band's hit points and what they need
    assert 36 * hit_points <= memory["hit_points"] <= 36 * hit_points + 1024 * band
    kept = cornell("kept", size=(640, 480))
    kept.run(passes=1)
    assert kept.stats()["memory"]["hit_points"] > 3 * memory["hit_points"]


def test_a_paused_streamed_pass_resumes_at_its_next_band_to_the_same_image():
    uninterrupted = cornell("streamed")
    uninterrupted.run(passes=3)
    renderer = cornell("streamed")
    renderer.run(passes=2)
    before = renderer.image()
    assert renderer.run(passes=1, pause_after=1e-9) == 0  # paused after its first band
    stats = renderer.stats()
    assert not stats["cancelled"] and stats["passes"] == 2 and stats["pass_done"] == pytest.approx(51 / 240)
    changed_rows = np.flatnonzero(np.any(renderer.image() != before, axis=(1, 2)))
    assert changed_rows.min() >= 240 - 51  # rows run bottom-up
    while renderer.stats()["passes"] < 3:
        renderer.run(passes=1, pause_after=1e-9)
    assert np.array_equal(renderer.image(), uninterrupted.image())


def test_a_render_cancelled_in_its_first_eye_pass_starts_it_again():
    uninterrupted = cornell("streamed")
    uninterrupted.run(passes=2)
    renderer = cornell("streamed", progress_interval=1e-6)
    calls = []

    def cancel(info):
        calls.append(info)
        return False

    assert renderer.run(passes=1, callback=cancel) == 0
    assert calls and renderer.stats()["cancelled"] and renderer.stats()["hit_points"] == 0
    assert renderer.run(passes=2) == 2
    assert np.array_equal(renderer.image(), uninterrupted.image())


def test_auto_keeps_hit_points_that_fit_and_streams_those_that_do_not():
    assert cornell("auto", size=(64, 48)).stats()["hit_point_storage"] == "kept"
    stochastic = ppm_core.Renderer(core_scenes.cornell_3spheres(64, 48), hit_points="stochastic")
    assert stochastic.stats()["hit_point_storage"] == ""
    # 9e8 pixels at 64 eye samples: tens of terabytes kept, more than any machine has.
    huge = ppm_core.Renderer(core_scenes.cornell_3spheres(30_000, 30_000), hit_points="fixed",
                             samples_per_pixel=64, photons_per_pass=1_000)
    stats = huge.stats()
    assert stats["hit_point_storage"] == "streamed"
    assert any("streamed instead" in line for line in stats["skipped"]), stats["skipped"]
    with pytest.raises(ValueError, match="hit_point_storage"):
        cornell("everywhere")


@pytest.mark.accuracy
def test_streamed_hit_points_reach_the_closed_spheres_radiance():
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, hit_points="fixed",
                                 hit_point_storage="streamed")
    renderer.run(passes=60)
    expected = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)
    assert renderer.image()[..., :3].mean() == pytest.approx(expected, rel=0.01)
