"""The house's layers point one way (docs/ARCHITECTURE.md, "Layers"): `make lint` runs this.

- C++: a folder of engine/ includes only itself and the folders before it in LAYERS.
- The add-on: no module of addon/ppm_render imports, at any depth of its code (functions included),
  a module that imports it back, directly or through others.

Prints each breach and exits 1 if there is one.
"""

import ast
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAYERS = ["base", "math", "geometry", "shading", "scene", "post", "ppm", "python"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/', re.MULTILINE)
ADDON = os.path.join(ROOT, "addon", "ppm_render")


def engine_breaches():
    breaches = []
    engine = os.path.join(ROOT, "engine")
    for layer in os.listdir(engine):
        if layer not in LAYERS:
            breaches.append(f"engine/{layer}: a folder outside the layers {LAYERS}")
            continue
        for folder, _, files in os.walk(os.path.join(engine, layer)):
            for name in files:
                path = os.path.join(folder, name)
                with open(path, encoding="utf-8") as f:
                    for used in INCLUDE.findall(f.read()):
                        if used in LAYERS and LAYERS.index(used) > LAYERS.index(layer):
                            breaches.append(f"{os.path.relpath(path, ROOT)} includes {used}/, a layer above {layer}/")
    return breaches


def module_name(path):
    relative = os.path.relpath(path, os.path.dirname(ADDON))[:-3].replace(os.sep, ".")
    return relative[: -len(".__init__")] if relative.endswith(".__init__") else relative


def imported_modules(path, name, modules):
    """The add-on modules that module `name` (its file `path`) imports anywhere in its code."""
    package = name if path.endswith("__init__.py") else name.rsplit(".", 1)[0]
    with open(path, encoding="utf-8") as f:
        tree = ast.parse(f.read(), path)
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = package
            for _ in range(node.level - 1):
                base = base.rsplit(".", 1)[0]
            base = (base + "." + node.module if node.module else base) if node.level else (node.module or "")
            submodules = [f"{base}.{alias.name}" for alias in node.names if f"{base}.{alias.name}" in modules]
            candidates = submodules or [base]  # `from . import x`: the module x; `from .m import f`: m
        elif isinstance(node, ast.Import):
            candidates = [alias.name for alias in node.names]
        else:
            continue
        found.update(c for c in candidates if c in modules and c != name)
    return found


def addon_cycles():
    paths = {}
    for folder, _, files in os.walk(ADDON):
        for file in files:
            if file.endswith(".py"):
                path = os.path.join(folder, file)
                paths[module_name(path)] = path
    graph = {name: imported_modules(path, name, paths) for name, path in paths.items()}
    # A package's __init__ importing its own modules is how packages are made: only other edges count.
    graph = {name: {m for m in uses if not (m.startswith(name + ".") and paths[name].endswith("__init__.py"))
                    and not (name.startswith(m + ".") and paths[m].endswith("__init__.py"))}
             for name, uses in graph.items()}
    cycles, state = [], {}

    def visit(name, stack):
        state[name] = "open"
        for used in sorted(graph[name]):
            if state.get(used) == "open":
                cycles.append(" -> ".join(stack[stack.index(used):] + [used]))
            elif used not in state:
                visit(used, stack + [used])
        state[name] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    return [f"add-on import circle: {cycle}" for cycle in cycles]


def main():
    breaches = engine_breaches() + addon_cycles()
    for breach in breaches:
        print(breach)
    print(f"check_layers: {len(breaches)} breach(es)" if breaches else "check_layers: the layers point one way")
    sys.exit(1 if breaches else 0)


if __name__ == "__main__":
    main()
