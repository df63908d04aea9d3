// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco job type: one PPM still rendered as shares of its passes on many workers, then merged
// (docs/FARM.md). Copy this file into the Flamenco Manager's `scripts/` folder and restart it.
// Workers need Blender with the PPM add-on zip installed and enabled, and shared storage for the
// .blend and the shares (as every Flamenco job does). Each share task runs
//   blender -b scene.blend --python-exit-code 1 --python-expr <find the add-on> -- share FIRST COUNT share.npz
// and the merge task, once every share is done,
//   blender -b --python-exit-code 1 --python-expr <find the add-on> -- merge out.exr share-*.npz

const JOB_TYPE = {
    label: "PPM Sharded Still",
    description: "One PPM still split into shares of its passes across workers, merged into one EXR",
    settings: [
        { key: "passes", type: "int32", required: true, eval: "C.scene.ppm.passes",
          description: "Photon passes in all (the scene's PPM Passes)" },
        { key: "shares", type: "int32", default: 16,
          description: "Tasks to split the passes into; the image is the same for any split" },
        { key: "render_output_path", type: "string", subtype: "file_path", required: true,
          eval: "str(Path(abspath(C.scene.render.filepath or '//'), jobname + '.exr'))",
          description: "The merged image (.exr); the shares go beside it in a folder of their own" },
        { key: "blender_cmd", type: "string", default: "{blender}", visible: "hidden" },
        { key: "blendfile", type: "string", required: true, visible: "web",
          description: "Path of the .blend file to render" },
    ],
};

// Imports the enabled add-on's farm/blender_task.py, whatever name Blender gave the add-on
// (ppm_render, or bl_ext.<repository>.ppm_render for an extension), and runs it.
const FIND_ADDON = "import sys, importlib; " +
    "name = next((n for n in sys.modules if n.split('.')[-1] == 'ppm_render'), None); " +
    "assert name, 'the PPM add-on is not enabled on this worker'; " +
    "importlib.import_module(name + '.farm.blender_task').main()";

function compileJob(job) {
    const settings = job.settings;
    const output = settings.render_output_path;
    if (!output.toLowerCase().endsWith(".exr")) throw "render_output_path must end in .exr";
    if (settings.passes < 1 || settings.shares < 1) throw "passes and shares must be at least 1";
    const sharesDir = path.join(path.dirname(output), path.basename(output, ".exr") + "-shares");

    const shares = Math.min(settings.shares, settings.passes);
    const merge = author.Task("merge", "blender");
    const shareFiles = [];
    for (let k = 0; k < shares; k++) {
        // Passes first .. first + count - 1: the ranges cover every pass once (farm/shares.py's plan).
        const first = Math.floor(settings.passes * k / shares);
        const count = Math.floor(settings.passes * (k + 1) / shares) - first;
        const file = path.join(sharesDir, `share-${first}-${count}.npz`);
        shareFiles.push(file);
        const task = author.Task(`share-${first}-${count}`, "blender");
        task.addCommand(author.Command("blender-render", {
            exe: settings.blender_cmd,
            exeArgs: "-b --python-exit-code 1",
            argsBefore: [],
            blendfile: settings.blendfile,
            args: ["--python-expr", FIND_ADDON, "--", "share", String(first), String(count), file],
        }));
        job.addTask(task);
        merge.addDependency(task);
    }
    merge.addCommand(author.Command("blender-render", {
        exe: settings.blender_cmd,
        exeArgs: "-b --python-exit-code 1",
        argsBefore: [],
        blendfile: settings.blendfile,
        args: ["--python-expr", FIND_ADDON, "--", "merge", output].concat(shareFiles),
    }));
    job.addTask(merge);
}
