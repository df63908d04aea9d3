"""The two estimators behind the render loop (engine/ppm/estimator.h): fixed hit points (PPM) and
stochastic hit points (SPPM) reach the same known answer, keep their statistics where they should,
and drop a cancelled pass without a trace."""

import numpy as np
import pytest

import core_scenes
import ppm_core

pytestmark = pytest.mark.accuracy

RADIUS, ALBEDO, POWER = 1.0, 0.5, 100.0
EXPECTED = core_scenes.expected_closed_sphere_radiance(RADIUS, ALBEDO, POWER)


def closed_sphere(hit_points, **settings):
    scene = core_scenes.closed_sphere_with_point_light(radius=RADIUS, albedo=ALBEDO, power=POWER)
    return ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, hit_points=hit_points, **settings)


def test_fixed_hit_points_come_from_one_eye_pass_and_stochastic_from_each_pass():
    fixed, stochastic = closed_sphere("fixed", samples_per_pixel=4), closed_sphere("stochastic")
    for renderer in (fixed, stochastic):
        renderer.run(passes=3)
    pixels = 32 * 32  # every pixel of the closed sphere sees its wall
    assert fixed.stats()["hit_points"] == 4 * pixels
    assert stochastic.stats()["hit_points"] == pixels  # the latest pass's, one eye sample per pixel
    assert fixed.stats()["seconds"]["eye_pass"] > 0.0 and stochastic.stats()["seconds"]["eye_pass"] > 0.0


@pytest.mark.parametrize("hit_points", ["fixed", "stochastic"])
def test_a_cancelled_pass_leaves_no_trace(hit_points):
    renderer = closed_sphere(hit_points, progress_interval=1e-6)
    renderer.run(passes=2)
    before, stats = renderer.image(), renderer.stats()
    calls = []

    def cancel_inside_the_pass(info):
        calls.append(info)
        return False

    assert renderer.run(passes=1, callback=cancel_inside_the_pass) == 0
    assert calls, "the callback should have been called inside the pass"
    after = renderer.stats()
    assert after["cancelled"] and after["passes"] == stats["passes"]
    assert after["photons_emitted"] == stats["photons_emitted"]
    assert np.array_equal(renderer.image(), before)


@pytest.mark.parametrize("threshold", [1, 10])
def test_stochastic_ppm_closed_sphere(threshold):
    scene = core_scenes.closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0)
    r = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, hit_points="stochastic", threshold=threshold)
    r.run(passes=80)
    expected = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)
    assert r.image()[..., :3].mean() == pytest.approx(expected, rel=0.01)



def test_stochastic_and_fixed_agree_on_the_cornell_box():
    def mean(**s):
        r = ppm_core.Renderer(core_scenes.cornell_3spheres(64, 48), photons_per_pass=50_000, threads=2, **s)
        r.run(passes=60)
        return r.image()[..., :3].mean(axis=(0, 1))

    np.testing.assert_allclose(mean(hit_points="stochastic"), mean(samples_per_pixel=4), rtol=0.03)



# Stochastic hit points are made in bands of rows (stochastic_hit_points.h): 512 x 320 pixels is
# three bands of 128 rows. The hit-point-indexed gather takes the image as one band.
BANDED = (512, 320)


def cornell(**settings):
    return ppm_core.Renderer(core_scenes.cornell_3spheres(*BANDED), photons_per_pass=20_000, threads=2,
                             hit_points="stochastic", **settings)


def test_stochastic_bands_make_the_image_of_one_band():
    banded, whole = cornell(gather="photons"), cornell(gather="hit_points")
    for r in (banded, whole):
        r.run(passes=3)
    # The same eye samples, photons and light samples: only the sums' rounding differs.
    a, b = banded.image(), whole.image()
    assert np.abs(a - b).max() <= 1e-4 * max(1.0, np.abs(b).max())
    assert banded.stats()["hit_points"] == whole.stats()["hit_points"] > BANDED[0] * BANDED[1] // 2


def test_a_cancelled_stochastic_pass_resumes_at_its_next_band():
    uninterrupted = cornell()
    uninterrupted.run(passes=4)
    renderer = cornell(progress_interval=1e-6)
    renderer.run(passes=3)
    before = renderer.image()
    shares = []

    def cancel_after_the_first_band(info):
        shares.append(info["pass_done"])
        return info["pass_done"] == 0.0

    assert renderer.run(passes=1, callback=cancel_after_the_first_band) == 0
    assert shares[-1] in (0.4, 0.8)  # 128 or 256 of the 320 rows
    stats = renderer.stats()
    assert stats["cancelled"] and stats["passes"] == 3
    changed_rows = np.flatnonzero(np.any(renderer.image() != before, axis=(1, 2)))
    # The completed bands show the pass, the rest not; rows run bottom-up.
    assert changed_rows.min() == 320 - 320 * shares[-1] and changed_rows.max() == 319
    assert renderer.run(passes=1) == 1
    assert np.array_equal(renderer.image(), uninterrupted.image())
    assert renderer.stats()["photons_emitted"] == uninterrupted.stats()["photons_emitted"]


def test_a_paused_pass_shows_its_finished_bands_and_ends_as_an_uninterrupted_one():
    """run(pause_after=...) returns between two bands of a pass (the viewport shows them) and the next
    run continues it, without the loss of a cancel."""
    uninterrupted = cornell()
    uninterrupted.run(passes=4)
    renderer = cornell()
    renderer.run(passes=3)
    before = renderer.image()
    assert renderer.run(passes=1, pause_after=1e-9) == 0  # paused after its first band
    stats = renderer.stats()
    assert not stats["cancelled"] and stats["passes"] == 3 and stats["pass_done"] == 0.4  # 128 of 320 rows
    changed_rows = np.flatnonzero(np.any(renderer.image() != before, axis=(1, 2)))
    assert changed_rows.min() == 320 - 128 and changed_rows.max() == 319  # rows run bottom-up
    runs = 1
    while renderer.stats()["passes"] < 4:
        renderer.run(passes=1, pause_after=1e-9)
        runs += 1
    assert runs == 3  # a band a run: 128, 128 and 64 rows
    assert np.array_equal(renderer.image(), uninterrupted.image())
    assert renderer.stats()["pass_done"] == 0.0
    fixed = ppm_core.Renderer(core_scenes.cornell_3spheres(*BANDED), photons_per_pass=2_000, threads=2,
                              hit_points="fixed")
    assert fixed.run(passes=1, pause_after=1e-9) == 1  # fixed hit points have no bands to pause between


def test_stochastic_memory_for_hit_points_does_not_grow_with_the_image():
    def memory(width, height):
        r = ppm_core.Renderer(core_scenes.cornell_3spheres(width, height), photons_per_pass=2_000, threads=2,
                              hit_points="stochastic")
        r.run(passes=1)
        return r.stats()["memory"]

    small, large = memory(512, 512), memory(2048, 2048)  # 4 bands of 128 rows, and 64 of 32
    band = 65536  # pixels (RenderContext::kBandPixels)
    # One band's hit points and what the eye pass, gather and direct light keep for them.
    assert small["hit_points"] <= 1024 * band and large["hit_points"] <= 1024 * band
    # pixel_stats.h: 52 bytes a pixel; error_estimate.h: 16
    assert large["pixels"] <= (52 + 16) * 2048 * 2048 * 1.01
    assert large["pixels"] >= 15 * small["pixels"]
