"""Error against stored references: renders every scene x variant x budget x seed and compares each
image with the scene's references (bench/references/, made by the `references` kind).

Parameters (see bench/experiments/convergence.toml for a full example):
- route: "core" (ppm_core with blend_scenes/core_scenes.py), "addon" (the .blend through the PPM
  add-on in bpy) or "cycles" (the .blend through Cycles); a variant may set its own route;
- scenes, size = [w, h], seeds (a variant may have its own), threads (2), and either `seconds` or
  `passes`: the budgets;
- settings: every variant's settings (Renderer arguments on the core route, scene.ppm or scene.cycles
  properties through Blender); variants: a list of tables (an optional `label`, settings); sweep:
  settings whose values are crossed with each variant;
- references: "ppm", "cycles" for a .blend (those stored), "core" for a core scene;
- regions: the regions of harness/regions.py to report (.blend scenes only);
- baseline: settings naming the variant every other is divided by, seed by seed;
- plot: draw error against wall time (error_vs_time.png); regions_plot: draw the first scene's
  regions (regions.png).

Measures (harness/metrics.py): relative MSE (mean over seeds, min-max), its ratio to the baseline's,
block relative RMSE (4x4 block means, blocks that see a light left out), RMSE, and the relative MSE
per region; slopes of log(error) against log(wall time) when there are several budgets.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from harness import metrics, plots
from harness.references import has_reference, load_reference, reference_noise


@dataclass
class Variant:
    label: str
    route: str
    settings: dict
    seeds: list


def variants(experiment):
    """The experiment's variants, each crossed with its sweep."""
    base = experiment.get("settings", {})
    sweep = experiment.get("sweep", {})
    keys = list(sweep)
    for explicit in experiment.get("variants", [{}]):
        for values in itertools.product(*(sweep[k] for k in keys)):
            swept = dict(zip(keys, values))
            settings = {**base, **explicit, **swept}
            route = settings.pop("route", experiment.get("route", "core"))
            seeds = settings.pop("seeds", experiment["seeds"])
            label = settings.pop("label", None)
            named = {k: v for k, v in {**explicit, **swept}.items() if k not in ("label", "seeds")}
            label = label or (", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                                        for k, v in named.items()) or "default")
            yield Variant(label, route, settings, seeds)


def budgets(experiment):
    if "passes" in experiment.params:
        return [("passes", n) for n in experiment["passes"]]
    return [("seconds", s) for s in experiment["seconds"]]


def budget_label(budget):
    unit, value = budget
    return f"{value} passes" if unit == "passes" else f"{value:g} s"


def render(variant, scene, size, seed, budget, threads):
    kwargs = dict(variant.settings, seed=seed, threads=threads, **{budget[0]: budget[1]})
    if variant.route == "core":
        from harness import core_route

        return core_route.render(scene, *size, **kwargs)
    from harness import addon_route

    draw = addon_route.render_cycles if variant.route == "cycles" else addon_route.render_ppm
    return draw(scene, *size, **kwargs)


class Scene:
    """One scene's references and region masks."""

    def __init__(self, name, experiment):
        self.name, self.size = name, experiment["size"]
        wanted = ["core"] if experiment.get("route", "core") == "core" else experiment.get("references", ["ppm"])
        self.references = {e: load_reference(name, e) for e in wanted if e == wanted[0] or has_reference(name, e)}
        first = next(iter(self.references.values()))[0]
        self.masks = {"all": np.ones(first.shape[:2], dtype=bool)}
        if experiment.get("regions"):
            from harness.regions import region_masks

            self.masks = region_masks(name, first, *self.size)
        self.unlit = None  # the pixels that see no light, where regions are known
        if experiment.get("regions"):
            self.unlit = ~self.masks["emitter"] if "emitter" in self.masks else self.masks["all"]

    def errors(self, image, engine, regions):
        reference, meta = self.references[engine]
        return {"rel_mse": metrics.rel_mse(image, reference), "rmse": metrics.rmse(image, reference),
                "rmse_unlit": metrics.rmse(image, reference, self.unlit) if self.unlit is not None else float("nan"),
                "block_rel_rmse": metrics.block_rel_rmse(image, reference),
                "ref_noise": reference_noise(meta),
                "regions": {k: metrics.rel_mse(image, reference, self.masks[k]) for k in regions if k in self.masks}}


def matches(variant, baseline):
    return bool(baseline) and all(({**variant.settings, "route": variant.route}).get(k) == v
                                  for k, v in baseline.items())


def run(experiment, results):
    size, threads = experiment["size"], experiment.get("threads", 2)
    regions = experiment.get("regions", [])
    all_variants = list(variants(experiment))
    rows = []
    for name in experiment["scenes"]:
        scene = Scene(name, experiment)
        noise = ", ".join(f"{e} {reference_noise(m):.1e}" for e, (_, m) in scene.references.items())
        results.note(f"{name}: references' own noise (rel. MSE): {noise}")
        if experiment.get("regions_plot") and name == experiment["scenes"][0]:
            plots.regions(name, scene.references[next(iter(scene.references))][0], scene.masks,
                          results.path("regions.png"))
        for budget in budgets(experiment):
            for variant in all_variants:
                for seed in variant.seeds:
                    r = render(variant, scene.name, size, seed, budget, threads)
                    for engine in scene.references:
                        row = dict(scene=name, reference=engine, variant=variant.label, route=variant.route,
                                   budget=budget_label(budget), seed=seed, wall=r.wall, passes=r.passes,
                                   **scene.errors(r.image, engine, regions))
                        rows.append(row)
                        results.row(**row)
                    print(f"{name} {variant.label} {budget_label(budget)} seed {seed}: wall {r.wall:.1f} s, "
                          f"rel. MSE {rows[-1]['rel_mse']:.3e}", flush=True)
    baseline = experiment.get("baseline", {})
    labels = {v.label for v in all_variants if matches(v, baseline)}
    table(results, rows, labels, regions)
    if len(budgets(experiment)) > 1:
        slopes(results, rows)
    if experiment.get("plot"):
        plots.error_against_time(curves(rows), results.path("error_vs_time.png"), experiment.title,
                                 (("rmse_unlit", "RMSE without the emitter pixels"),
                                  ("rel_mse", "relative MSE (eps 0.01); thin lines: reference noise")))


def groups(rows, *keys):
    out = {}
    for r in rows:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def number(value, fmt):
    return f"{value:{fmt}}" if np.isfinite(value) else ""


def spread(values, fmt):
    values = np.asarray(values)
    return f"{values.mean():{fmt}}" + (f" ({values.min():{fmt}}-{values.max():{fmt}})" if len(values) > 1 else "")


def mean(runs, key, fmt):
    values = [r[key] for r in runs]
    return "" if None in values else number(float(np.mean(values)), fmt)


def table(results, rows, baseline_labels, regions):
    """One line per scene, reference, variant and budget: means over seeds (min-max where it matters),
    and the ratio to the baseline's relative MSE, seed by seed (runs in the same order)."""
    shown = [k for k in regions if any(k in r["regions"] for r in rows)]
    header = ["scene", "reference", "variant", "budget", "wall (s)", "passes", "rel. MSE", "/ baseline's",
              "block rel. RMSE", "RMSE", "RMSE w/o emitter"] + [f"rel. MSE {k}" for k in shown]
    grouped = groups(rows, "scene", "reference", "variant", "budget")
    out = []
    for (scene, ref, label, budget), runs in grouped.items():
        base = next((b for (s, e, lab, bud), b in grouped.items()
                     if (s, e, bud) == (scene, ref, budget) and lab in baseline_labels), None)
        ratio = f"{np.mean([r['rel_mse'] / b['rel_mse'] for r, b in zip(runs, base)]):.3f}" if base else ""
        cells = [scene, ref, label, budget, mean(runs, "wall", ".1f"), mean(runs, "passes", ".0f"),
                 spread([r["rel_mse"] for r in runs], ".3e"), ratio, spread([r["block_rel_rmse"] for r in runs], ".4f"),
                 mean(runs, "rmse", ".4f"), mean(runs, "rmse_unlit", ".4f")]
        cells += [f"{np.mean([r['regions'][k] for r in runs]):.2e}" if k in runs[0]["regions"] else "" for k in shown]
        out.append(cells)
    results.table(header, out)


def curves(rows):
    """Mean over seeds, per (scene, reference, variant): rows in budget order."""
    out = {}
    for (scene, ref, label), runs in groups(rows, "scene", "reference", "variant").items():
        points = []
        for _, same in groups(runs, "budget").items():
            points.append({k: float(np.mean([r[k] for r in same]))
                           for k in ("wall", "rel_mse", "rmse", "rmse_unlit", "ref_noise")})
        out[f"{scene}, {label}" + ("" if ref in ("ppm", "core") else f" (vs {ref} ref.)")] = points
    return out


def slopes(results, rows):
    out = []
    for label, points in curves(rows).items():
        t = [p["wall"] for p in points]
        cells = []
        for key in ("rmse", "rmse_unlit", "rel_mse"):
            ys = [p[key] for p in points]
            cells.append(number(metrics.log_slope(t, ys), ".2f") if np.all(np.isfinite(ys)) else "")
        out.append([label] + cells)
    results.table(["scene, variant", "RMSE slope", "RMSE w/o emitter slope", "rel. MSE slope"], out,
                  title="Slopes of log(error) against log(wall time)")
