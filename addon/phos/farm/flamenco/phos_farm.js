// Phos render job type for Flamenco 3.x (a "job compiler script").
//
// Install: copy this file into the `scripts` folder next to the
// `flamenco-manager` executable and restart the Manager; the job type is then
// called "phos-farm" (Flamenco names it after the file, `_` becoming `-`).
// See docs/farm.md for the farm workflow this job type drives.
//
// The task graph is the one our Python farm tool builds (docs/farm.md):
//
//   cache                       one task; builds the caches of the key frames
//     |                         (none with caches "per-frame": then every
//     |                         task makes its own frame's caches and waits
//     |                         for nothing)
//     |
//     +-- frame-F               regions "1x1": one task per frame F,
//     |                         each waiting for `cache`
//     |
//     +-- region-F-I            otherwise: one task per frame F and region
//           |                   index I (0 .. columns*rows-1), each waiting
//           |                   for `cache`,
//           +-- stitch-F        and one task per frame waiting for all the
//                               region tasks of that frame
//
// Every task runs Blender through Flamenco's `blender-render` command:
//
//   {blender} {blenderArgs} BLENDFILE --python-exit-code 1
//       --python-expr PHOS_BOOTSTRAP -- SUBCOMMAND --job-dir DIR ...
//
// PHOS_BOOTSTRAP finds the installed Phos add-on (legacy add-on or extension,
// whatever its package path), enables it and hands the arguments after `--`
// to phos.farm.blender_task.main(). Caches, frames and reports all go to the
// job directory, a folder every worker must reach at the same path (or
// through a Flamenco two-way variable).
//
// This file runs in Flamenco's embedded JavaScript engine (goja, compiled in
// strict mode) and in our Node test (tests/farm/flamenco_job.test.mjs), so it
// uses no modules and no Node or browser APIs: only the globals Flamenco
// gives a job compiler script (`author`, `print`) and the `job` object
// passed to compileJob().

// The Python run by every task. Kept on one line: a Python test compares it
// with the constant of the same name on the Python side. It must not contain
// curly braces, which Flamenco reads as variables such as {blender}.
const PHOS_BOOTSTRAP = "import addon_utils,importlib;n=next((m.__name__ for m in addon_utils.modules() if m.__name__.rsplit('.',1)[-1]=='phos'),'');assert n,'Phos farm: error: the Phos add-on is not installed in this Blender';addon_utils.enable(n,default_set=False);importlib.import_module(n+'.farm.blender_task').main()";

// The job type as Flamenco shows it in Blender's submission panel and in the
// Manager's web interface. Setting fields follow Flamenco's AvailableJobSetting
// schema (key, type, subtype, label, description, default, eval, evalInfo,
// visible, required).
const JOB_TYPE = {
    label: "Phos Render",
    description: "Render with Phos: build the caches once, then render each frame, or each region of each frame and stitch them",
    settings: [
        {
            key: "frames",
            type: "string",
            label: "Frames",
            required: true,
            eval: "'%d-%d' % (C.scene.frame_start, C.scene.frame_end)",
            evalInfo: { showLinkButton: true, description: "The scene's frame range" },
            description: "Frames to render: single frames and inclusive ranges, separated by commas, e.g. '1-250' or '1-10, 20, 30-40'",
        },
        {
            key: "regions",
            type: "string",
            label: "Regions",
            required: true,
            default: "1x1",
            description: "Split each frame into COLUMNSxROWS regions rendered by separate tasks and stitched afterwards; '1x1' renders whole frames",
        },
        {
            key: "caches",
            type: "string",
            label: "Caches",
            choices: ["shared", "per-frame"],
            required: false,
            default: "shared",
            description: "'shared': one cache task makes the photon maps and the irradiance cache for every frame (only the camera moves); 'per-frame': each frame makes its own (objects, lights or materials animate)",
        },
        {
            key: "key_frames",
            type: "string",
            label: "Key Frames",
            required: false,
            default: "",
            description: "Frames whose caches are built, in the same notation as Frames; empty means every frame to render",
        },
        {
            key: "job_dir",
            type: "string",
            subtype: "dir_path",
            label: "Job Directory",
            required: true,
            description: "Shared folder, reachable by every worker, where this job's caches, frames and reports go",
        },
        {
            // Flamenco's Blender add-on fills a string setting with this exact
            // key with the path of the blend file it sent to the farm. The
            // eval is only a fallback for other submitters; "web" keeps it out
            // of the submission panel but shows it in the Manager's job view.
            key: "blendfile",
            type: "string",
            subtype: "file_path",
            label: "Blend File",
            required: true,
            eval: "bpy.data.filepath",
            visible: "web",
            description: "The blend file every task opens",
        },
    ],
};

// Blender's highest frame number (MAXFRAME). Scene frame ranges start at 0 or
// later, so this job type takes non-negative frame numbers only, even though
// Blender can show negative frames in its timeline.
const PHOS_MAX_FRAME = 1048574;

// Guards against a typo such as "1-1000000" flooding the Manager with tasks.
const PHOS_MAX_TASKS = 100000;

// Longest --key-frames argument accepted. Linux refuses a single argument of
// 128 KiB or more; Windows caps a whole command line at 32767 characters, so
// farms with Windows workers need far fewer key frames than this.
const PHOS_MAX_ARG_CHARS = 100000;

function compileJob(job) {
    const settings = job.settings;

    const blendfile = requireText(settings, "blendfile", "the blend file to render");
    const jobDir = requireJobDir(settings);
    const frames = parseFrameList(settingText(settings, "frames", ""), "frames");
    const regions = parseRegions(settingText(settings, "regions", "1x1"));
    const keyFrames = chooseKeyFrames(frames, settingText(settings, "key_frames", ""));
    const shared = parseCaches(settingText(settings, "caches", "shared"));

    checkTaskCount(frames, regions, shared);
    const keyList = formatFrameList(keyFrames);
    if (keyList.length > PHOS_MAX_ARG_CHARS) {
        fail("key_frames: " + keyFrames.length + " key frames make a command line too long for Blender; "
            + "give fewer key frames in the Key Frames setting");
    }

    var after = [];
    var own = ["--caches", "per-frame"];
    if (shared) {
        const cacheTask = authorCacheTask(blendfile, jobDir, frames, keyList);
        job.addTask(cacheTask);
        after = [cacheTask];
        own = [];
    }

    if (regions.count === 1) {
        authorFrameTasks(job, after, own, blendfile, jobDir, frames);
    } else {
        authorRegionTasks(job, after, own, blendfile, jobDir, frames, regions);
    }

    print("phos-farm: " + frames.length + " frame(s), regions " + regions.text
        + ", " + keyFrames.length + " key frame(s), job dir " + jobDir);
}

// ---------------------------------------------------------------------------
// Tasks. Flamenco copies a task when it is added to the job, so each task gets
// its command and dependencies before job.addTask().

function authorCacheTask(blendfile, jobDir, frames, keyList) {
    const args = phosArgs("cache", jobDir, [
        "--frames", formatFrameList(frames),
        "--key-frames", keyList,
    ]);
    return blenderTask("cache", blendfile, args, []);
}

function authorFrameTasks(job, after, own, blendfile, jobDir, frames) {
    for (var i = 0; i < frames.length; i++) {
        const frame = String(frames[i]);
        const args = phosArgs("frame", jobDir, ["--frame", frame].concat(own));
        job.addTask(blenderTask("frame-" + frame, blendfile, args, after));
    }
}

function authorRegionTasks(job, after, own, blendfile, jobDir, frames, regions) {
    for (var i = 0; i < frames.length; i++) {
        const frame = String(frames[i]);
        const regionTasks = [];
        for (var region = 0; region < regions.count; region++) {
            const args = phosArgs("region", jobDir, [
                "--frame", frame,
                "--region", String(region),
                "--regions", regions.text,
            ].concat(own));
            const task = blenderTask("region-" + frame + "-" + region, blendfile, args, after);
            job.addTask(task);
            regionTasks.push(task);
        }
        const stitchArgs = phosArgs("stitch", jobDir, ["--frame", frame, "--regions", regions.text]);
        job.addTask(blenderTask("stitch-" + frame, blendfile, stitchArgs, regionTasks));
    }
}

// One task of type "blender" running one `blender-render` command; the
// command line is: {blender} {blenderArgs} BLENDFILE ARGS...
function blenderTask(name, blendfile, args, dependencies) {
    const task = author.Task(name, "blender");
    task.addCommand(author.Command("blender-render", {
        exe: "{blender}",
        exeArgs: "{blenderArgs}",
        argsBefore: [],
        blendfile: blendfile,
        args: args,
    }));
    for (var i = 0; i < dependencies.length; i++) {
        task.addDependency(dependencies[i]);
    }
    return task;
}

// Blender arguments after the blend file: run the bootstrap, fail the task
// when Python fails, and pass SUBCOMMAND --job-dir DIR EXTRA... to Phos.
function phosArgs(subcommand, jobDir, extra) {
    const head = [
        "--python-exit-code", "1",
        "--python-expr", PHOS_BOOTSTRAP,
        "--",
        subcommand,
        "--job-dir", jobDir,
    ];
    return head.concat(extra);
}

// ---------------------------------------------------------------------------
// Settings. Every problem throws an Error; Flamenco refuses the job and shows
// the message to whoever submitted it.

function fail(message) {
    throw new Error("Phos farm job: " + message);
}

function settingText(settings, key, fallback) {
    const value = settings[key];
    if (value === undefined || value === null) {
        return fallback;
    }
    return String(value);
}

function requireText(settings, key, what) {
    const text = settingText(settings, key, "");
    if (text.trim() === "") {
        fail(key + ": " + what + " is missing");
    }
    return text;
}

function requireJobDir(settings) {
    const jobDir = requireText(settings, "job_dir", "the shared job directory");
    if (jobDir.indexOf("//") === 0) {
        // A blend-file-relative path would resolve next to the copy of the
        // blend file on the farm, a different folder for every job.
        fail("job_dir: '" + jobDir + "' is relative to the blend file; give an absolute path to a shared folder");
    }
    return jobDir;
}

// Parses "1-10, 20, 30-40": comma-separated frames and inclusive ranges
// A-B, whitespace allowed around every number. Returns the frames sorted
// ascending without duplicates. Non-negative integers only (see
// PHOS_MAX_FRAME).
function parseFrameList(text, key) {
    const trimmed = text.trim();
    if (trimmed === "") {
        fail(key + ": no frames given; use e.g. '1-250' or '1-10,20,30-40'");
    }
    const seen = {};
    const frames = [];
    const parts = trimmed.split(",");
    for (var i = 0; i < parts.length; i++) {
        const range = parseFramePart(parts[i], text, key);
        if (range.last - range.first + 1 > PHOS_MAX_TASKS) {
            fail(key + ": the range '" + parts[i].trim() + "' has more than " + PHOS_MAX_TASKS + " frames");
        }
        for (var frame = range.first; frame <= range.last; frame++) {
            if (!seen[frame]) {
                seen[frame] = true;
                frames.push(frame);
            }
        }
        if (frames.length > PHOS_MAX_TASKS) {
            fail(key + ": '" + text + "' has more than " + PHOS_MAX_TASKS + " frames");
        }
    }
    frames.sort(function (a, b) { return a - b; });
    return frames;
}

function parseFramePart(part, text, key) {
    const piece = part.trim();
    const single = /^(\d+)$/.exec(piece);
    if (single) {
        const frame = frameNumber(single[1], text, key);
        return { first: frame, last: frame };
    }
    const range = /^(\d+)\s*-\s*(\d+)$/.exec(piece);
    if (!range) {
        fail(key + ": cannot read '" + piece + "' in '" + text + "'; expected frames such as '7' or ranges "
            + "such as '1-250' (non-negative whole numbers), separated by commas");
    }
    const first = frameNumber(range[1], text, key);
    const last = frameNumber(range[2], text, key);
    if (first > last) {
        fail(key + ": the range '" + piece + "' ends before it starts");
    }
    return { first: first, last: last };
}

function frameNumber(digits, text, key) {
    const frame = parseInt(digits, 10);
    if (frame > PHOS_MAX_FRAME) {
        fail(key + ": frame " + digits + " in '" + text + "' is past Blender's last frame " + PHOS_MAX_FRAME);
    }
    return frame;
}

// Formats sorted frames back as ranges, e.g. [1,2,3,7] gives "1-3,7". The
// cache task gets the frame list in this compact form.
function formatFrameList(frames) {
    const pieces = [];
    var start = 0;
    while (start < frames.length) {
        var end = start;
        while (end + 1 < frames.length && frames[end + 1] === frames[end] + 1) {
            end++;
        }
        pieces.push(end === start ? String(frames[start]) : frames[start] + "-" + frames[end]);
        start = end + 1;
    }
    return pieces.join(",");
}

// Parses "CxR" (columns x rows, both at least 1; "X" and spaces allowed).
function parseRegions(text) {
    const match = /^\s*(\d+)\s*[xX]\s*(\d+)\s*$/.exec(text);
    if (!match) {
        fail("regions: cannot read '" + text + "'; expected COLUMNSxROWS such as '1x1' or '2x2'");
    }
    const columns = parseInt(match[1], 10);
    const rows = parseInt(match[2], 10);
    if (columns < 1 || rows < 1) {
        fail("regions: '" + text + "' needs at least one column and one row");
    }
    if (columns * rows > PHOS_MAX_TASKS) {
        fail("regions: '" + text + "' makes more than " + PHOS_MAX_TASKS + " regions per frame");
    }
    return { columns: columns, rows: rows, count: columns * rows, text: columns + "x" + rows };
}

// Key frames default to every frame to render; given ones must all be frames
// that this job renders.
function chooseKeyFrames(frames, text) {
    if (text.trim() === "") {
        return frames.slice();
    }
    const keys = parseFrameList(text, "key_frames");
    const rendered = {};
    for (var i = 0; i < frames.length; i++) {
        rendered[frames[i]] = true;
    }
    const outside = [];
    for (var k = 0; k < keys.length; k++) {
        if (!rendered[keys[k]]) {
            outside.push(keys[k]);
        }
    }
    if (outside.length > 0) {
        fail("key_frames: " + formatFrameList(outside) + " not among the frames to render ("
            + formatFrameList(frames) + ")");
    }
    return keys;
}

function parseCaches(text) {
    const caches = text.trim();
    if (caches !== "shared" && caches !== "per-frame") {
        fail("caches: '" + text + "' is not 'shared' or 'per-frame'");
    }
    return caches === "shared";
}

function checkTaskCount(frames, regions, shared) {
    const perFrame = regions.count === 1 ? 1 : regions.count + 1;
    const total = (shared ? 1 : 0) + frames.length * perFrame;
    if (total > PHOS_MAX_TASKS) {
        fail(frames.length + " frame(s) with regions " + regions.text + " make " + total
            + " tasks, more than " + PHOS_MAX_TASKS + "; render fewer frames or regions per job");
    }
}
