"""An experiment is a small TOML file in bench/experiments/: its kind (a module of bench/kinds/), a
title, and the kind's parameters. A `[quick]` table overrides parameters for a smoke run (a minute or
so, figures meaningless); `--set key=value` overrides one parameter from the command line.
`base = "name"` starts from another file's parameters; a file whose name starts with "_" is such a
base only, not an experiment."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import tomllib

EXPERIMENTS_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "experiments")


@dataclass
class Experiment:
    name: str  # the file's stem
    kind: str
    title: str
    params: dict = field(default_factory=dict)
    quick: bool = False

    def __getitem__(self, key):
        return self.params[key]

    def get(self, key, default=None):
        return self.params.get(key, default)


def merged(base, override):
    """`base` with `override`'s keys replaced, tables merged key by key."""
    out = dict(base)
    for key, value in override.items():
        out[key] = merged(out[key], value) if isinstance(value, dict) and isinstance(out.get(key), dict) else value
    return out


def parse_value(text):
    """A command-line value as TOML (numbers, booleans, lists, quoted strings), else the bare string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def available():
    return sorted(f[:-5] for f in os.listdir(EXPERIMENTS_DIR) if f.endswith(".toml") and not f.startswith("_"))


def read(name):
    """The file's data; `base = "other"` starts from bench/experiments/other.toml's (a set of
    experiments that share a baseline)."""
    path = os.path.join(EXPERIMENTS_DIR, f"{name}.toml")
    if not os.path.exists(path):
        raise SystemExit(f"no experiment {name!r}; there are: {', '.join(available())}")
    with open(path, "rb") as f:
        data = tomllib.load(f)
    base = data.pop("base", None)
    return merged(read(base), data) if base else data


def load(name, quick=False, overrides=()):
    """The experiment `name` (bench/experiments/<name>.toml), with its quick table and `overrides`
    ("key=value" strings; a dotted key reaches into a table) applied."""
    data = read(name)
    quick_table = data.pop("quick", {})
    kind, title = data.pop("kind"), data.pop("title")
    params = merged(data, quick_table) if quick else data
    for item in overrides:
        key, _, value = item.partition("=")
        *tables, last = key.strip().split(".")
        target = params
        for t in tables:
            target = target.setdefault(t, {})
        target[last] = parse_value(value.strip())
    return Experiment(name, kind, title, params, quick)
