"""Render control: cancel latency, time limits, progress callbacks, determinism."""

import threading
import time

import pytest

import core_scenes
import ppm_core


def test_cancel_from_callback_is_prompt_on_a_large_render():
    scene = core_scenes.cornell_3spheres(1920, 1080)
    renderer = ppm_core.Renderer(scene, photons_per_pass=2_000_000, threads=2, progress_interval=0.05)
    asked = []

    def callback(info):
        if info["seconds"] > 0.3 and not asked:
            asked.append(time.perf_counter())
        return not asked

    renderer.run(passes=1000, callback=callback)
    latency = time.perf_counter() - asked[0]
    assert latency < 0.5, f"cancel took {latency:.2f} s"
    assert renderer.stats()["cancelled"]


def test_cancel_from_another_thread():
    scene = core_scenes.cornell_3spheres(320, 240)
    renderer = ppm_core.Renderer(scene, photons_per_pass=500_000, threads=2)
    timer = threading.Timer(0.5, renderer.cancel)
    start = time.perf_counter()
    timer.start()
    renderer.run(passes=100_000)
    assert time.perf_counter() - start < 1.5
    assert renderer.stats()["cancelled"]
    # The renderer keeps working after a cancel.
    assert renderer.run(passes=1) == 1


def test_time_limit_and_progress():
    scene = core_scenes.cornell_3spheres(160, 120)
    renderer = ppm_core.Renderer(scene, photons_per_pass=50_000, threads=2)
    seen = []
    start = time.perf_counter()
    passes = renderer.run(seconds=1.0, callback=lambda info: seen.append(info["passes"]))
    elapsed = time.perf_counter() - start
    assert 1.0 <= elapsed < 1.6
    assert passes >= 1 and not renderer.stats()["cancelled"]
    assert seen and seen == sorted(seen)


def test_exception_in_callback_propagates():
    renderer = ppm_core.Renderer(core_scenes.cornell_3spheres(64, 48), photons_per_pass=10_000)

    def callback(info):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        renderer.run(passes=5, callback=callback)


def test_stats_report_work_and_memory_stays_flat():
    scene = core_scenes.cornell_3spheres(64, 48)
    renderer = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=2)
    renderer.run(passes=5)
    first = renderer.stats()
    renderer.run(passes=200)
    later = renderer.stats()
    assert later["passes"] == 205 and later["photons_emitted"] == 205 * 5_000
    assert later["hit_points"] > 0 and later["photons_deposited"] > 0
    assert later["memory_bytes"] <= first["memory_bytes"] * 1.05
    assert later["radius_mean"] < first["radius_mean"]
    assert set(later["seconds"]) >= {"eye_pass", "photon_trace", "direct_light", "progressive_update"}


def test_reading_the_image_during_a_run_is_a_clear_error():
    renderer = ppm_core.Renderer(core_scenes.cornell_3spheres(64, 48), photons_per_pass=10_000)
    errors = []

    def callback(info):
        try:
            renderer.image()
        except RuntimeError as e:
            errors.append(str(e))
        return False

    renderer.run(passes=3, callback=callback)
    assert errors and "while run() is in progress" in errors[0]
    assert renderer.image().shape == (48, 64, 4)  # fine between runs
