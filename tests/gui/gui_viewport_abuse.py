"""Runs inside a real Blender GUI (Xvfb): what users do to a viewport while it renders with PPM, one
step every 0.4 s: toggle Solid and Rendered, move and reshape an object, add a cube and subdivide it
in Edit Mode, delete the object being rendered, undo, change frames,
turn on a render border in the camera view and a viewport render region, turn the 3D viewport
into another editor and back, open another file, and quit mid-render.

    xvfb-run -a -s "-screen 0 1600x900x24" blender --factory-startup scene.blend \
        -P tests/gui/gui_viewport_abuse.py -- --out DIR

DIR/status.json lists the steps done (written before each step, so a crash shows where) and the
viewport's error text, if any.
"""

import json
import os
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, ROOT)
import render

OUT = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "/tmp"
DONE = []
WINDOWS = {}
PARTS = {}  # what the viewport updated after an edit: changed_part of its sessions


def context():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type in ("VIEW_3D", "IMAGE_EDITOR"))
    return window, area


def shading(kind):
    _window, area = context()
    area.spaces.active.shading.type = kind


def move_ball():
    bpy.data.objects["matte_ball"].location.x += 0.1


def reshape_ball():
    mesh = bpy.data.objects["matte_ball"].data
    for vertex in mesh.vertices[:30]:
        vertex.co.z += 0.03
    mesh.update()


def delete_ball():
    bpy.data.objects.remove(bpy.data.objects["matte_ball"])


def add_cube():
    window, area = context()
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        bpy.ops.mesh.primitive_cube_add(size=0.3, location=(0.2, 0.0, 0.4))


def mode(kind):
    window, area = context()
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        bpy.ops.object.mode_set(mode=kind)


def subdivide():
    """In Edit Mode: every edge of the cube cut once (more triangles)."""
    window, area = context()
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.mesh.subdivide(number_cuts=1)


def undo():
    window, area = context()
    with bpy.context.temp_override(window=window, screen=window.screen, area=area):
        bpy.ops.ed.undo_push(message="before undo")
        bpy.ops.ed.undo()


def editor(kind):
    _window, area = context()
    area.type = kind


def open_other():
    bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "blend_scenes", "cornell_diffuse.blend"))


def prepare():
    scene = bpy.context.scene
    scene.render.engine = "PPM"
    scene.ppm.viewport_photons_per_pass = 20_000


def camera_border():
    render = bpy.context.scene.render
    render.use_border = True
    render.border_min_x, render.border_max_x, render.border_min_y, render.border_max_y = 0.25, 0.75, 0.2, 0.6
    _window, area = context()
    area.spaces.active.region_3d.view_perspective = "CAMERA"


def viewport_region():
    bpy.context.scene.render.use_border = False
    _window, area = context()
    space = area.spaces.active
    space.region_3d.view_perspective = "PERSP"
    space.use_render_border = True
    space.render_border_min_x, space.render_border_max_x = 0.1, 0.4
    space.render_border_min_y, space.render_border_max_y = 0.5, 0.9


def note_window(name):
    """Records the rendered window's size against the region's."""
    from ppm_render import viewport

    _window, area = context()
    region = next(r for r in area.regions if r.type == "WINDOW")
    views = [s.view for s in viewport.SESSIONS if s.view is not None]
    WINDOWS[name] = {"region": [region.width, region.height],
                     "rendered": [views[0]["width"], views[0]["height"]] if views else None}


def note_part(name):
    from ppm_render import viewport

    PARTS[name] = sorted({s.last_part or "" for s in viewport.SESSIONS})


def errors():
    from ppm_render import viewport

    return [s.error for s in viewport.SESSIONS if s.error]


STEPS = [
    ("rendered", lambda: shading("RENDERED")),
    ("solid", lambda: shading("SOLID")),
    ("rendered again", lambda: shading("RENDERED")),
    ("move the object (in place)", move_ball),
    ("note what it updated", lambda: note_part("moved")),
    ("reshape it (in place)", reshape_ball),
    ("note what that updated", lambda: note_part("reshaped")),
    ("add a cube (in place)", add_cube),
    ("note what adding updated", lambda: note_part("added")),
    ("edit mode", lambda: mode("EDIT")),
    ("subdivide the cube in edit mode (in place)", subdivide),
    ("note what subdividing updated", lambda: note_part("subdivided")),
    ("object mode", lambda: mode("OBJECT")),
    ("delete the object", delete_ball),
    ("note what deleting updated", lambda: note_part("deleted")),
    ("undo", undo),
    ("move it after the undo", move_ball),
    ("frame 10", lambda: bpy.context.scene.frame_set(10)),
    ("stronger lamp", lambda: setattr(bpy.data.lights[0], "energy", bpy.data.lights[0].energy * 2.0)),
    ("fewer viewport photons", lambda: setattr(bpy.context.scene.ppm, "viewport_photons_per_pass", 10_000)),
    ("render border in the camera view", camera_border),
    ("note it", lambda: note_window("camera border")),
    ("viewport render region", viewport_region),
    ("note that", lambda: note_window("viewport region")),
    ("image editor", lambda: editor("IMAGE_EDITOR")),
    ("3D viewport", lambda: editor("VIEW_3D")),
    ("rendered after the editor", lambda: shading("RENDERED")),
    ("open another file", open_other),
    ("prepare it", prepare),
    ("rendered in it", lambda: shading("RENDERED")),
    ("wait", lambda: None),
]


def write(status):
    with open(os.path.join(OUT, "status.json"), "w") as f:
        json.dump(status, f, indent=1)


def step():
    if len(DONE) == len(STEPS):
        import threading

        from ppm_render import viewport

        running = [t for t in threading.enumerate() if t.name == "PPM viewport" and t.is_alive()]
        write({"steps": DONE, "complete": True, "errors": errors(), "render_threads": len(running),
               "sessions": len(viewport.SESSIONS), "windows": WINDOWS, "parts": PARTS})
        bpy.ops.wm.quit_blender()  # while the viewport refines
        return None
    name, action = STEPS[len(DONE)]
    write({"steps": DONE + [name + " (started)"], "complete": False})
    action()
    DONE.append(name)
    return 0.4


def main():
    render.make_core_importable()
    render.ensure_addon(bpy)
    prepare()
    bpy.app.timers.register(step, first_interval=1.0, persistent=True)  # survives opening a file


main()
