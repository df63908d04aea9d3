"""Runs inside a real Blender GUI (Xvfb): the 3D viewport in Rendered shading with PPM, a light moved
by script while it refines, and what the viewport shows photographed.

    xvfb-run -a -s "-screen 0 1600x900x24" blender --factory-startup scene.blend \
        -P tests/gui/gui_viewport.py -- --out DIR

Timers drive it as a user would: switch the viewport to the camera view in Rendered shading
(overlays off, so the region shows only the image), wait, screenshot the region (the window, DIR/viewport_1.png)
and record the session's newest image; move the lamp; record the time from the edit to the first
redrawn image of the new scene and to full resolution; screenshot again (viewport_2.png); write
DIR/status.json and quit.
"""

import json
import os
import sys
import time

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
import render

OUT = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "/tmp"
SETTLE = 4.0  # seconds of refinement before a screenshot
STATE = {"step": "start", "at": None, "events": []}


def view3d():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        if area.type == "VIEW_3D":
            region = next(r for r in area.regions if r.type == "WINDOW")
            return window, area, region
    raise RuntimeError("no 3D viewport")


def session():
    from ppm_render import viewport

    sessions = list(viewport.SESSIONS)
    return sessions[0] if sessions else None


def screenshot(name):
    window, area, region = view3d()
    path = os.path.join(OUT, name)
    with bpy.context.temp_override(window=window, screen=window.screen, area=area, region=region):
        bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=1)
        bpy.ops.screen.screenshot(filepath=path, check_existing=False)  # the window: crop with "region"
    return path


def record(name):
    s = session()
    image = s.newest() if s else None
    shot = screenshot(f"{name}.png")
    path = os.path.join(OUT, f"{name}_image.npy")
    if image is not None:
        np.save(path, image.rgba)
    _window, area, region = view3d()
    STATE[name] = {"screenshot": shot, "image": path if image is not None else None,
                   "passes": image.passes if image else 0, "pixel_size": image.pixel_size if image else 0,
                   "generation": image.generation if image else 0, "error": s.error if s else "no session",
                   "region": [region.x, region.y, region.width, region.height],
                   "window": [bpy.context.window_manager.windows[0].width,
                              bpy.context.window_manager.windows[0].height]}


def start():
    window, area, region = view3d()
    space = area.spaces.active
    space.region_3d.view_perspective = "CAMERA"
    space.overlay.show_overlays = False
    space.shading.type = "RENDERED"
    STATE["step"], STATE["at"] = "first", time.monotonic()


def move_lamp():
    lamp = bpy.context.scene.objects["lamp"]
    lamp.location.x += 0.5
    STATE["step"], STATE["at"] = "second", time.monotonic()
    STATE["edited_generation"] = session().generation


def poll():
    now = time.monotonic()
    if STATE["at"] is None:
        return 0.1
    s = session()
    if STATE["step"] == "first" and now - STATE["at"] > SETTLE:
        record("viewport_1")
        move_lamp()
    elif STATE["step"] == "second":
        image = s.newest() if s else None
        new = image is not None and image.generation > STATE["edited_generation"]
        if new and "first_frame_s" not in STATE:
            STATE["first_frame_s"] = now - STATE["at"]
        if new and image.pixel_size == 1 and "full_resolution_s" not in STATE:
            STATE["full_resolution_s"] = now - STATE["at"]
        if now - STATE["at"] > SETTLE:
            record("viewport_2")
            finish()
            return None
    if now - STATE.get("started", now) > 100:
        finish()
        return None
    return 0.01


def finish():
    with open(os.path.join(OUT, "status.json"), "w") as f:
        json.dump({**STATE, "engine": bpy.context.scene.render.engine,
                   "view_transform": bpy.context.scene.view_settings.view_transform}, f, indent=1)
    bpy.ops.wm.quit_blender()


def main():
    render.make_core_importable()
    render.ensure_addon(bpy)
    scene = bpy.context.scene
    scene.render.engine = "PPM"
    scene.view_settings.view_transform = "Standard"  # so the test can predict the screen's values
    scene.view_settings.look = "None"
    scene.ppm.viewport_photons_per_pass = 20_000
    STATE["started"] = time.monotonic()
    bpy.app.timers.register(start, first_interval=1.0)
    bpy.app.timers.register(poll, first_interval=1.1)


main()
