// Unit test of the Phos Flamenco job type (addon/phos/farm/flamenco/phos_farm.js).
//
//     node --test tests/farm/flamenco_job.test.mjs
//
// The script is loaded into a bare `vm` context, in strict mode as Flamenco's
// goja engine compiles it, with stand-ins for the job-author interface that
// Flamenco documents for job compiler scripts:
//   author.Task(name, type)      -> task with addCommand(cmd), addDependency(task)
//   author.Command(type, params) -> command
//   job.settings, job.addTask(task), print(...)
// Like Flamenco's Manager, job.addTask() keeps a copy of the task, so the fake
// refuses any change to a task after it was added (Flamenco would drop it).

import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import vm from "node:vm";

const SCRIPT_PATH = fileURLToPath(
    new URL("../../addon/phos/farm/flamenco/phos_farm.js", import.meta.url));
const SOURCE = readFileSync(SCRIPT_PATH, "utf8");

const BOOTSTRAP = "import addon_utils,importlib;n=next((m.__name__ for m in addon_utils.modules() if m.__name__.rsplit('.',1)[-1]=='phos'),'');assert n,'Phos farm: error: the Phos add-on is not installed in this Blender';addon_utils.enable(n,default_set=False);importlib.import_module(n+'.farm.blender_task').main()";

const BLEND = "/farm/jobs/shot/shot.flamenco.blend";
const DIR = "/farm/phos/shot_010";

// ---------------------------------------------------------------------------
// Fake Flamenco environment.

function makeAuthor() {
    let nextId = 1;
    return {
        Task(name, type) {
            assert.equal(arguments.length, 2, "author.Task takes (name, type)");
            assert.equal(typeof name, "string");
            assert.equal(typeof type, "string");
            assert.ok(name.trim() !== "", "task name is required");
            assert.ok(type.trim() !== "", "task type is required");
            const task = {
                id: nextId++,
                name,
                type,
                commands: [],
                dependencies: [],
                added: false,
                addCommand(command) {
                    assert.ok(!task.added, `task ${name}: command added after job.addTask()`);
                    assert.ok(command && command.isCommand, "addCommand takes an author.Command");
                    task.commands.push(command);
                },
                addDependency(dep) {
                    assert.ok(!task.added, `task ${name}: dependency added after job.addTask()`);
                    assert.ok(dep && dep.isTask, "addDependency takes an author.Task");
                    task.dependencies.push(dep);
                },
                isTask: true,
            };
            return task;
        },
        Command(type, params) {
            assert.equal(typeof type, "string");
            assert.equal(typeof params, "object");
            return { isCommand: true, type, params };
        },
    };
}

function makeJob(settings) {
    const job = {
        settings: { ...settings },
        tasks: [],
        addTask(task) {
            assert.ok(task && task.isTask, "job.addTask takes an author.Task");
            assert.ok(!task.added, `task ${task.name} added twice`);
            task.added = true;
            // Snapshot, as Flamenco copies the task into the job.
            job.tasks.push({
                id: task.id,
                name: task.name,
                type: task.type,
                commands: task.commands.map((c) => ({ type: c.type, params: structuredClone(c.params) })),
                deps: task.dependencies.map((d) => d.name),
                depIds: task.dependencies.map((d) => d.id),
            });
        },
    };
    return job;
}

// Loads the script into a fresh context; returns its globals and the log.
function load() {
    const printed = [];
    const context = vm.createContext({
        author: makeAuthor(),
        print: (...args) => printed.push(args.map(String).join(" ")),
    });
    vm.runInContext('"use strict";\n' + SOURCE, context, { filename: "phos_farm.js" });
    const get = (name) => vm.runInContext(name, context);
    return {
        compileJob: get("compileJob"),
        JOB_TYPE: get("JOB_TYPE"),
        PHOS_BOOTSTRAP: get("PHOS_BOOTSTRAP"),
        printed,
    };
}

function compile(settings) {
    const script = load();
    const job = makeJob({ blendfile: BLEND, job_dir: DIR, regions: "1x1", key_frames: "", ...settings });
    script.compileJob(job);
    return { tasks: job.tasks, printed: script.printed, settings: job.settings };
}

// The exact Blender arguments (after the blend file) of a Phos task.
function phosArgs(subcommand, ...extra) {
    return ["--python-exit-code", "1", "--python-expr", BOOTSTRAP, "--", subcommand, "--job-dir", DIR, ...extra];
}

function byName(tasks) {
    const map = new Map();
    for (const task of tasks) {
        assert.ok(!map.has(task.name), `duplicate task name ${task.name}`);
        map.set(task.name, task);
    }
    return map;
}

// Checks the single blender-render command of a task and returns its args.
function renderArgs(task) {
    assert.equal(task.type, "blender", `${task.name}: task type`);
    assert.equal(task.commands.length, 1, `${task.name}: one command`);
    const { type, params } = task.commands[0];
    assert.equal(type, "blender-render");
    assert.deepEqual(Object.keys(params).sort(), ["args", "argsBefore", "blendfile", "exe", "exeArgs"]);
    assert.equal(params.exe, "{blender}");
    assert.equal(params.exeArgs, "{blenderArgs}");
    assert.deepEqual(params.argsBefore, []);
    assert.equal(params.blendfile, BLEND);
    for (const arg of params.args) {
        assert.equal(typeof arg, "string", `${task.name}: every argument is a string`);
    }
    return params.args;
}

// Every dependency is a task of the same job, added before the task itself.
function assertDepsInJob(tasks) {
    const position = new Map(tasks.map((t, i) => [t.id, i]));
    tasks.forEach((task, i) => {
        for (const id of task.depIds) {
            assert.ok(position.has(id), `${task.name} depends on a task not in the job`);
            assert.ok(position.get(id) < i, `${task.name} is added before its dependency`);
        }
    });
}

function compileError(settings) {
    try {
        compile(settings);
    } catch (err) {
        return err;
    }
    assert.fail(`no error for ${JSON.stringify(settings)}`);
}

// ---------------------------------------------------------------------------
// The script itself.

test("script is a plain script: no modules, no Node APIs", () => {
    assert.doesNotMatch(SOURCE, /^\s*(import|export)\s/m);
    assert.doesNotMatch(SOURCE, /\brequire\s*\(/);
    assert.doesNotMatch(SOURCE, /\bprocess\./);
    assert.doesNotMatch(SOURCE, /\bconsole\./);
    assert.equal(typeof load().compileJob, "function");
});

test("PHOS_BOOTSTRAP is the exact Python, on one line in double quotes", () => {
    const { PHOS_BOOTSTRAP } = load();
    assert.equal(PHOS_BOOTSTRAP, BOOTSTRAP);
    const lines = SOURCE.split("\n").filter((l) => l.startsWith("const PHOS_BOOTSTRAP"));
    assert.deepEqual(lines, [`const PHOS_BOOTSTRAP = "${BOOTSTRAP}";`]);
    assert.doesNotMatch(BOOTSTRAP, /[{}]/, "no Flamenco variable braces");
});

test("JOB_TYPE declares the settings with Flamenco's documented fields", () => {
    const { JOB_TYPE } = load();
    assert.equal(typeof JOB_TYPE.label, "string");
    assert.ok(JOB_TYPE.label.length > 0);
    const documented = new Set(["key", "type", "subtype", "choices", "propargs", "description", "label",
        "default", "eval", "evalInfo", "visible", "required", "editable"]);
    const types = new Set(["string", "int32", "float", "bool"]);
    const subtypes = new Set(["file_path", "dir_path", "file_name", "hashed_file_path"]);
    const visibilities = new Set(["visible", "hidden", "submission", "web"]);
    const keys = JOB_TYPE.settings.map((s) => s.key);
    assert.deepEqual([...keys].sort(), ["blendfile", "caches", "frames", "job_dir", "key_frames", "regions"]);
    for (const s of JOB_TYPE.settings) {
        for (const field of Object.keys(s)) {
            assert.ok(documented.has(field), `${s.key}: undocumented field ${field}`);
        }
        assert.ok(types.has(s.type), `${s.key}: type`);
        assert.equal(s.type, "string");
        if ("subtype" in s) assert.ok(subtypes.has(s.subtype), `${s.key}: subtype`);
        if ("visible" in s) assert.ok(visibilities.has(s.visible), `${s.key}: visible`);
        if ("required" in s) assert.equal(typeof s.required, "boolean");
        if ("eval" in s) assert.equal(typeof s.eval, "string");
        if ("default" in s) assert.equal(typeof s.default, "string");
        assert.equal(typeof s.description, "string", `${s.key}: description`);
        if ("evalInfo" in s) {
            assert.equal(typeof s.evalInfo.showLinkButton, "boolean");
            assert.equal(typeof s.evalInfo.description, "string");
        }
    }
    const setting = Object.fromEntries(JOB_TYPE.settings.map((s) => [s.key, s]));
    assert.deepEqual([...setting.caches.choices], ["shared", "per-frame"]);
    assert.equal(setting.caches.default, "shared");
    assert.equal(setting.blendfile.eval, "bpy.data.filepath");
    assert.equal(setting.blendfile.required, true);
    assert.notEqual(setting.blendfile.visible ?? "visible", "visible", "blendfile is not asked from the artist");
    assert.equal(setting.frames.required, true);
    assert.match(setting.frames.eval, /C\.scene\.frame_start/);
    assert.match(setting.frames.eval, /C\.scene\.frame_end/);
    assert.equal(setting.regions.default, "1x1");
    assert.equal(setting.key_frames.default, "");
    assert.equal(setting.key_frames.required, false);
    assert.equal(setting.job_dir.required, true);
    assert.equal(setting.job_dir.subtype, "dir_path");
    // Flamenco turns the job type into JSON (its etag is a hash of that):
    // nothing may be lost on the way (no functions, no undefined values).
    assert.deepEqual(JSON.parse(JSON.stringify(JOB_TYPE)), structuredClone(JOB_TYPE));
});

// ---------------------------------------------------------------------------
// Task graphs.

test("4 frames, 1x1: cache + one task per frame, each after cache", () => {
    const { tasks, printed } = compile({ frames: "1-4" });
    assert.deepEqual(tasks.map((t) => t.name), ["cache", "frame-1", "frame-2", "frame-3", "frame-4"]);
    const named = byName(tasks);
    assert.deepEqual(renderArgs(named.get("cache")),
        phosArgs("cache", "--frames", "1-4", "--key-frames", "1-4"));
    assert.deepEqual(named.get("cache").deps, []);
    for (const f of [1, 2, 3, 4]) {
        const task = named.get(`frame-${f}`);
        assert.deepEqual(renderArgs(task), phosArgs("frame", "--frame", String(f)));
        assert.deepEqual(task.deps, ["cache"]);
    }
    assertDepsInJob(tasks);
    assert.equal(printed.length, 1);
});

test("2 frames, 2x2: cache + 8 regions + 2 stitches", () => {
    const { tasks } = compile({ frames: "5,9", regions: "2x2" });
    assert.equal(tasks.length, 11);
    const named = byName(tasks);
    assert.deepEqual(renderArgs(named.get("cache")),
        phosArgs("cache", "--frames", "5,9", "--key-frames", "5,9"));
    for (const f of ["5", "9"]) {
        for (const i of ["0", "1", "2", "3"]) {
            const task = named.get(`region-${f}-${i}`);
            assert.ok(task, `region-${f}-${i} exists`);
            assert.deepEqual(renderArgs(task),
                phosArgs("region", "--frame", f, "--region", i, "--regions", "2x2"));
            assert.deepEqual(task.deps, ["cache"]);
        }
        const stitch = named.get(`stitch-${f}`);
        assert.deepEqual(renderArgs(stitch), phosArgs("stitch", "--frame", f, "--regions", "2x2"));
        assert.deepEqual(stitch.deps, [0, 1, 2, 3].map((i) => `region-${f}-${i}`));
    }
    assert.equal(tasks.filter((t) => t.name.startsWith("frame-")).length, 0);
    assertDepsInJob(tasks);
});

test("3x1 regions: indices 0..2 and the regions argument as given", () => {
    const { tasks } = compile({ frames: "7", regions: " 3 X 1 " });
    assert.deepEqual(tasks.map((t) => t.name), ["cache", "region-7-0", "region-7-1", "region-7-2", "stitch-7"]);
    assert.deepEqual(renderArgs(tasks[3]), phosArgs("region", "--frame", "7", "--region", "2", "--regions", "3x1"));
});

test("frame lists: ranges, singles, whitespace, duplicates, order", () => {
    const { tasks } = compile({ frames: " 30-32 , 3,1-2, 2 ,10 " });
    assert.deepEqual(tasks.map((t) => t.name),
        ["cache", "frame-1", "frame-2", "frame-3", "frame-10", "frame-30", "frame-31", "frame-32"]);
    assert.deepEqual(renderArgs(tasks[0]),
        phosArgs("cache", "--frames", "1-3,10,30-32", "--key-frames", "1-3,10,30-32"));
});

test("frame 0 is a frame", () => {
    const { tasks } = compile({ frames: "0-1" });
    assert.deepEqual(tasks.map((t) => t.name), ["cache", "frame-0", "frame-1"]);
});

test("key frames: empty means every frame, explicit list is kept sorted", () => {
    const every = compile({ frames: "1-10,20,30-32", key_frames: "" }).tasks[0];
    assert.deepEqual(renderArgs(every), phosArgs("cache", "--frames", "1-10,20,30-32",
        "--key-frames", "1-10,20,30-32"));

    const blank = compile({ frames: "1-3", key_frames: "   " }).tasks[0];
    assert.deepEqual(renderArgs(blank), phosArgs("cache", "--frames", "1-3", "--key-frames", "1-3"));

    const missing = compile({ frames: "1-3", key_frames: undefined }).tasks[0];
    assert.deepEqual(renderArgs(missing), phosArgs("cache", "--frames", "1-3", "--key-frames", "1-3"));

    const listed = compile({ frames: "1-250", key_frames: "200, 1,100,100" });
    assert.deepEqual(renderArgs(listed.tasks[0]), phosArgs("cache", "--frames", "1-250", "--key-frames", "1,100,200"));
    assert.equal(listed.tasks.length, 251, "key frames do not change the frame tasks");
});

test("regions default to 1x1 when the setting is absent", () => {
    const { tasks } = compile({ frames: "1-2", regions: undefined });
    assert.deepEqual(tasks.map((t) => t.name), ["cache", "frame-1", "frame-2"]);
});

test("compiling twice in one context gives the same tasks", () => {
    const script = load();
    const a = makeJob({ blendfile: BLEND, job_dir: DIR, frames: "1-3", regions: "2x1", key_frames: "2" });
    const b = makeJob({ blendfile: BLEND, job_dir: DIR, frames: "1-3", regions: "2x1", key_frames: "2" });
    script.compileJob(a);
    script.compileJob(b);
    const strip = (tasks) => tasks.map(({ id, depIds, ...rest }) => rest);
    assert.deepEqual(strip(a.tasks), strip(b.tasks));
});

// ---------------------------------------------------------------------------
// Refused jobs: an Error whose message names the setting.

function assertRefused(settings, pattern) {
    const err = compileError(settings);
    assert.ok(err instanceof Error || (err && err.constructor && err.constructor.name === "Error"),
        `throws an Error, got ${err}`);
    assert.match(err.message, /^Phos farm job: /);
    assert.match(err.message, pattern);
}

test("bad frames are refused", () => {
    for (const frames of ["", "   ", "a", "1-", "-5", "1--3", "1,,2", "1,", "5-1", "1.5", "1-2-3", "2000000"]) {
        assertRefused({ frames }, /^Phos farm job: frames: /);
    }
    assertRefused({ frames: "a" }, /'a'/);
    assertRefused({ frames: "5-1" }, /ends before it starts/);
});

test("bad regions are refused", () => {
    for (const regions of ["0x2", "2x0", "ax2", "2", "2x", "x2", "2x2x2", "-1x2", "", "1.5x2"]) {
        assertRefused({ frames: "1-2", regions }, /^Phos farm job: regions: /);
    }
    assertRefused({ frames: "1", regions: "0x2" }, /at least one column and one row/);
});

test("key frames outside the frames are refused", () => {
    assertRefused({ frames: "1-10", key_frames: "0,5" }, /^Phos farm job: key_frames: 0 not among/);
    assertRefused({ frames: "1-10", key_frames: "5,11-12" }, /key_frames: 11-12 not among the frames to render \(1-10\)/);
    assertRefused({ frames: "1-10,20", key_frames: "15" }, /key_frames: 15 not among/);
    assertRefused({ frames: "1-10", key_frames: "x" }, /^Phos farm job: key_frames: cannot read/);
});

test("an empty job dir is refused, as is a blend-relative one", () => {
    assertRefused({ frames: "1", job_dir: "" }, /^Phos farm job: job_dir: /);
    assertRefused({ frames: "1", job_dir: "  " }, /job_dir: /);
    assertRefused({ frames: "1", job_dir: undefined }, /job_dir: /);
    assertRefused({ frames: "1", job_dir: "//farm" }, /job_dir: .*relative to the blend file/);
});

test("a missing blend file is refused", () => {
    assertRefused({ frames: "1", blendfile: "" }, /^Phos farm job: blendfile: /);
});

test("absurd task counts are refused before building tasks", () => {
    assertRefused({ frames: "0-1000000" }, /frames: the range '0-1000000' has more than 100000 frames/);
    assertRefused({ frames: "1-1000", regions: "20x10" }, /201001 tasks/);
});

test("caches per-frame: no cache task, every task makes its own and waits for nothing", () => {
    const { tasks } = compile({ frames: "3-4", regions: "1x2", caches: "per-frame" });
    assert.deepEqual(tasks.map((t) => t.name), ["region-3-0", "region-3-1", "stitch-3", "region-4-0", "region-4-1", "stitch-4"]);
    assert.deepEqual(renderArgs(tasks[1]), phosArgs("region", "--frame", "3", "--region", "1", "--regions", "1x2",
        "--caches", "per-frame"));
    assert.deepEqual(tasks[0].deps, []);
    assert.deepEqual(tasks[2].deps, ["region-3-0", "region-3-1"]);
    const whole = compile({ frames: "7", caches: "per-frame" }).tasks;
    assert.deepEqual(whole.map((t) => t.name), ["frame-7"]);
    assert.deepEqual(renderArgs(whole[0]), phosArgs("frame", "--frame", "7", "--caches", "per-frame"));
    assertRefused({ frames: "1-2", caches: "sometimes" }, /^Phos farm job: caches: 'sometimes' is not/);
});
