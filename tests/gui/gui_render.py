"""Runs inside a real Blender GUI (Xvfb): press F12 the way Blender does and photograph the result.

    xvfb-run -a -s "-screen 0 1600x900x24" blender --factory-startup scene.blend -P tests/gui/gui_render.py -- --out DIR

A timer starts bpy.ops.render.render('INVOKE_DEFAULT') once the UI is up; when the
render_complete handler fires, the render window (an Image Editor showing
"Render Result") is screenshotted to DIR/render_window.png, a mid-render
screenshot goes to DIR/progress.png, DIR/status.json records what was seen,
and Blender quits.
"""

import json
import os
import sys
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
import render

OUT = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "/tmp"
STATE = {"started": None, "completed": False, "progress_shot": False, "stats": []}


def finish(status):
    with open(os.path.join(OUT, "status.json"), "w") as f:
        json.dump({**STATE, **status}, f, indent=1)
    bpy.ops.wm.quit_blender()


def render_window():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR" and area.spaces.active.image is not None \
                    and area.spaces.active.image.type == "RENDER_RESULT":
                return window, area
    return None, None


def screenshot(name):
    window, area = render_window()
    if window is None:
        return None
    path = os.path.join(OUT, name)
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=1)  # a complete frame, not one mid-draw
        bpy.ops.screen.screenshot(filepath=path, check_existing=False)
    return path


def start():
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.render.render("INVOKE_DEFAULT")  # what F12 does
    STATE["started"] = time.monotonic()


def poll():
    if STATE["started"] is None:
        return 0.2
    elapsed = time.monotonic() - STATE["started"]
    if not STATE["completed"]:
        if elapsed > 5.0 and not STATE["progress_shot"]:
            STATE["progress_shot"] = screenshot("progress.png") is not None
        if elapsed > 120:
            finish({"ok": False, "error": "render did not complete in 120 s"})
            return None
        return 0.25
    if elapsed < STATE["completed_at"] + 1.0:
        return 0.25  # let the window redraw the final image
    _window, area = render_window()
    path = screenshot("render_window.png")
    finish({"ok": path is not None, "engine": bpy.context.scene.render.engine,
            "windows": len(bpy.context.window_manager.windows),
            "image_editor_shows": area.spaces.active.image.name if area else None, "screenshot": path})
    return None


def on_complete(*args):
    STATE["completed"] = True
    STATE["completed_at"] = time.monotonic() - STATE["started"]


def main():
    render.make_core_importable()
    render.ensure_addon(bpy)
    scene = bpy.context.scene
    scene.render.engine = "PPM"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 480, 360, 100
    scene.ppm.passes, scene.ppm.photons_per_pass, scene.ppm.samples_per_pixel = 30, 50_000, 2
    bpy.app.handlers.render_complete.append(on_complete)
    bpy.app.handlers.render_cancel.append(on_complete)
    bpy.app.timers.register(start, first_interval=1.5)
    bpy.app.timers.register(poll, first_interval=2.0)


main()
