"""PPM: a progressive photon mapping render engine for Blender (package ppm_render).

Loads as an extension (blender_manifest.toml, Blender 4.2+) and as a legacy
add-on (bl_info, Blender 3.4). Registration order: settings first (the engine
and panels read them), then the engine, panels and the revolve object.
"""

bl_info = {
    "name": "PPM Render",
    "description": "Progressive photon mapping render engine with an exact Bezier revolve object",
    "author": "PPM project",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > PPM; Add > Curve > Bezier Revolve",
    "category": "Render",
}

from . import bezier_revolve, engine, properties, ui

MODULES = (properties, engine, ui, bezier_revolve)


def register():
    for module in MODULES:
        module.register()


def unregister():
    for module in reversed(MODULES):
        module.unregister()
