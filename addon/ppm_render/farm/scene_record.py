"""An exported core scene as plain data: the builder calls the add-on's export made, with their
arguments (numbers, strings, numpy arrays), replayed on another machine into the same
ppm_core.Scene (shares.render_share). A worker then needs ppm_core and numpy, not Blender.

The export runs against a RecordingCore in place of the ppm_core module: its Scene forwards every
call to a real ppm_core.Scene (the export reads back what it needs: texture counts, constant-folded
node programs) and keeps the calls that change it. Replaying them in order gives each object,
material and texture the same index as at export.
"""

from __future__ import annotations

# Calls that only read the scene: not recorded (the node compiler folds constants with run_program
# once per constant node).
QUERIES = frozenset({"intersect", "run_program", "texture_info", "camera_rays", "geometry_layout", "light_count",
                     "primitive_count", "subtrees_built", "texture_count", "triangles_copied", "grid_info",
                     "grid_count"})


class RecordedScene:
    """A ppm_core.Scene whose changes are kept in `calls`: (name, args, kwargs), or ("=", name, value)
    for an attribute set."""

    def __init__(self, core_module):
        object.__setattr__(self, "core_module", core_module)
        object.__setattr__(self, "scene", core_module.Scene())
        object.__setattr__(self, "calls", [])

    def __getattr__(self, name):
        value = getattr(self.scene, name)
        if not callable(value) or name in QUERIES:
            return value

        def recorded(*args, **kwargs):
            result = value(*args, **kwargs)  # first: a call the core refuses is not recorded
            self.calls.append((name, args, kwargs))
            return result

        return recorded

    def __setattr__(self, name, value):
        setattr(self.scene, name, value)
        self.calls.append(("=", name, value))


class RecordingCore:
    """Stands in for the ppm_core module during an export: Scene() records; the rest is ppm_core's."""

    def __init__(self, core_module):
        self.core = core_module
        self.scenes = []

    def Scene(self):  # noqa: N802 - the module's name for it
        scene = RecordedScene(self.core)
        self.scenes.append(scene)
        return scene

    def __getattr__(self, name):
        return getattr(self.core, name)

