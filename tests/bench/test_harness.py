"""The benchmark harness (bench/run.py): experiments as data, the metrics, and one small experiment
run end to end through the core route."""

from __future__ import annotations

import json
import os
import sys

import numpy as np
import pytest

BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "bench")
sys.path.insert(0, BENCH)
import run  # noqa: E402
from harness import experiment, metrics  # noqa: E402


def test_metrics_are_zero_on_the_reference_and_scale_as_defined():
    rng = np.random.default_rng(1)
    reference = rng.uniform(0.1, 2.0, (24, 32, 3))
    assert metrics.rel_mse(reference, reference) == 0.0
    assert metrics.rmse(reference, reference) == 0.0
    assert metrics.block_rel_rmse(reference, reference) == 0.0
    brighter = reference * 1.1
    assert metrics.rel_rmse(brighter, reference) == pytest.approx(
        np.sqrt(np.mean((0.1 * reference) ** 2)) / reference.mean())
    assert metrics.block_rel_rmse(brighter, reference) == pytest.approx(
        np.sqrt(np.mean((0.1 * metrics.blocks(reference)) ** 2)) / metrics.blocks(reference).mean())
    assert metrics.log_slope([1, 2, 4, 8], [1, 0.5, 0.25, 0.125]) == pytest.approx(-1.0)


def test_halves_noise_estimates_the_error_of_the_mean():
    rng = np.random.default_rng(2)
    truth = np.full((200, 200, 3), 1.0)
    a, b = (truth + rng.normal(0.0, 0.1, truth.shape) for _ in range(2))
    # The mean of two halves with standard deviation 0.1 each has variance 0.01 / 2.
    assert metrics.halves_noise(a, b)["rmse"] == pytest.approx(np.sqrt(0.005), rel=0.02)
    assert metrics.rmse(0.5 * (a + b), truth) == pytest.approx(np.sqrt(0.005), rel=0.02)


def test_block_measure_leaves_out_blocks_that_see_a_light():
    reference = np.ones((16, 16, 3))
    reference[:4, :4] = 500.0  # a light in one block
    image = reference.copy()
    image[:4, :4] = 100.0  # wrong only at the light
    assert metrics.block_rel_rmse(image, reference) == 0.0
    assert metrics.rel_mse(image, reference) > 0.0


def test_an_experiment_starts_from_its_base_then_quick_then_the_command_line():
    e = experiment.load("ablation_threshold_passes", quick=True, overrides=["seeds=[4]", "settings.alpha=0.5"])
    assert e.kind == "accuracy"
    assert e["scenes"] == ["cornell_3spheres"]  # its own, over the base's two
    assert e["passes"] == [5, 20]  # its quick table
    assert e["seeds"] == [4]  # the command line
    assert e["settings"]["alpha"] == 0.5 and e["settings"]["photons_per_pass"] == 50000  # merged tables
    assert "_ablation" not in experiment.available()
    assert experiment.parse_value("[1, 2]") == [1, 2] and experiment.parse_value("fixed") == "fixed"


def test_every_experiment_names_a_kind_that_imports():
    import importlib

    for name in experiment.available():
        e = experiment.load(name)
        assert e.title, name
        module = importlib.import_module(f"kinds.{e.kind}")  # an import sorted before its path breaks here
        assert callable(module.run), name


def test_an_accuracy_experiment_runs_end_to_end_and_more_passes_mean_less_error(tmp_path, monkeypatch):
    from harness import results

    monkeypatch.setattr(results, "BENCH_DIR", str(tmp_path))
    code = run.main(["ablation_threshold_passes", "--quick", "--set", "passes=[2, 16]", "--set", "seeds=[1]",
                     "--set", "sweep.threshold=[1, 10]"])
    assert code == 0
    folder = tmp_path / "out" / "ablation_threshold_passes"
    rows = json.loads((folder / "rows.json").read_text())
    assert {(r["variant"], r["budget"]) for r in rows} == {
        (f"threshold {p}", f"{n} passes") for p in (1, 10) for n in (2, 16)}
    for p in (1, 10):
        error = {r["budget"]: r["rel_mse"] for r in rows if r["variant"] == f"threshold {p}"}
        assert error["16 passes"] < error["2 passes"]
    assert {r["passes"] for r in rows} == {2, 16}
    report = (folder / "report.md").read_text()
    assert "| cornell_3spheres | core | threshold 10 | 16 passes |" in report
