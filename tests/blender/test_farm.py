# SPDX-License-Identifier: GPL-3.0-or-later
"""Render farms (docs/farm.md): `python3 -m phos.farm` runs a job's cache
task once, then its frames or regions, each a `blender -b` of its own, on
local processes or on a real single-machine Slurm cluster
(tests/farm/slurm_cluster.py, started and stopped here as root; skipped
with the reason where that cannot be). What a farm renders must be what
one process renders with the same caches, bit for bit: the frames of an
animation whose camera moves, a still split into 2 × 2 regions and
stitched, a task killed mid-render and requeued, a task resubmitted. A
cache made before a material changed is refused, naming what differs.
Flamenco's job type builds the same graph (its compile step is tested
under Node.js, tests/farm/flamenco_job.test.mjs)."""

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

import bpy
import numpy as np
import pytest

import exrread
import phostest as pt

FARM_DIR = os.path.join(pt.REPO_DIR, "tests", "farm")
sys.path.insert(0, FARM_DIR)
import slurm_cluster  # noqa: E402

# The Python that runs the farm's command line: any Python 3 (it needs no
# bpy); Blender's own where it is a Python executable (bpy builds).
FARM_PYTHON = (sys.executable if os.path.basename(sys.executable).startswith("python")
               else shutil.which("python3"))
FRAMES = (1, 2, 3, 4)


def _farm_env(tmp_dir):
    """The command line's environment: the farm package from this tree;
    and for the add-on from the source tree, a user scripts folder whose
    addons/phos is it, so that every task's Blender finds it (an
    installed extension is found as users have it)."""
    env = dict(os.environ, PYTHONPATH=pt.ADDON_DIR)
    if pt.FROM_SOURCE_TREE:
        env["BLENDER_USER_SCRIPTS"] = pt.user_scripts_dir(tmp_dir)
    return env


def farm(tmp_dir, *args, env=None, check=True, timeout=600):
    """Run `python3 -m phos.farm ARGS`; (exit code, output)."""
    proc = subprocess.run([FARM_PYTHON, "-m", "phos.farm"] + [str(a) for a in args], env=env or _farm_env(tmp_dir),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout)
    out = proc.stdout.decode("utf-8", "replace")
    if check:
        assert proc.returncode == 0, "phos.farm %s failed:\n%s" % (" ".join(map(str, args)), out)
    return proc.returncode, out


def submit(tmp_dir, blend, job_dir, *args, env=None, check=True):
    return farm(tmp_dir, "submit", blend, "--job-dir", job_dir, "--blender", shlex.join(pt.BLENDER_COMMAND),
                *args, env=env, check=check)


def pixels(path):
    """An EXR's RGBA as uint32 bit patterns, for comparisons bit for bit."""
    ch = exrread.read_channels(path)
    return np.stack([ch[c] for c in "RGBA"], axis=-1).astype(np.float32).view(np.uint32)


def assert_same_image(path, ref_path):
    a, b = pixels(path), pixels(ref_path)
    assert a.shape == b.shape, "%s is %s, %s is %s" % (path, a.shape, ref_path, b.shape)
    differ = np.count_nonzero(np.any(a != b, axis=-1))
    assert differ == 0, "%s differs from %s in %d of %d pixels" % (path, ref_path, differ, a.shape[0] * a.shape[1])
    assert np.mean(b.view(np.float32)[..., :3]) > 0.01, "%s is black: the comparison shows nothing" % ref_path


def task_state(job_dir, name):
    with open(os.path.join(job_dir, "tasks", name + ".json")) as f:
        return json.load(f)


def task_log(job_dir, name):
    with open(os.path.join(job_dir, "logs", name + ".log")) as f:
        return f.read()


# ------------------------------------------------------------------ scenes

def make_blend(path, width, height, samples, box_moves=False):
    """A floor, a box and a point lamp under a dim world, PHOTON with the
    irradiance cache (photon maps and cache both used), the camera moving
    over frames 1-4 (and the box too if box_moves); saved to `path`."""
    scene = pt.reset_file()
    pt.add_plane(scene, "Floor", size=6.0, material=pt.diffuse("Floor", (0.7, 0.7, 0.7)))
    pt.add_cube(scene, "Box", size=1.0, location=(0, 0, 0.5), material=pt.diffuse("Box", (0.8, 0.3, 0.2)))
    pt.add_light(scene, "POINT", 500.0, location=(2, -2, 3), name="Lamp")
    pt.add_camera(scene, location=(0, -5, 2), target=(0, 0, 0.5))
    pt.set_world(scene, (0.05, 0.05, 0.05))
    pt.configure_output(scene, width, height)
    pt.configure_phos(scene, samples, max_bounces=4, seed=3)
    scene.phos.integrator = "PHOTON"
    scene.phos.global_photons, scene.phos.caustic_photons = 20000, 2000
    scene.render.engine = "PHOS"
    scene.frame_start, scene.frame_end = FRAMES[0], FRAMES[-1]
    cam = scene.camera
    cam.keyframe_insert("location", frame=1)
    cam.location = (1.5, -4.5, 2.2)
    cam.keyframe_insert("location", frame=4)
    if box_moves:
        box = bpy.data.objects["Box"]
        box.keyframe_insert("location", frame=1)
        box.location = (0.6, 0.3, 0.5)
        box.keyframe_insert("location", frame=4)
    bpy.ops.wm.save_as_mainfile(filepath=str(path), copy=True)
    pt.reset_file()
    return str(path)


REFERENCE_SCRIPT = """
import sys, bpy, phostest as pt
blend, jobs = sys.argv[sys.argv.index("--") + 1], sys.argv[sys.argv.index("--") + 2:]
bpy.ops.wm.open_mainfile(filepath=blend)
pt.enable_addon()
from phos.farm import blender_task as bt
for spec in jobs:   # JOB_DIR:KEYS:FRAMES, caches and frames in this one process (KEYS -: per frame)
    job_dir, keys, frames = spec.split(":")
    scene = bpy.context.scene
    if keys != "-":
        bt.run_cache(scene, job_dir, [int(f) for f in keys.split(",")])
    for f in frames.split(","):
        bt.run_frame(scene, job_dir, int(f), shared=keys != "-")
"""


def render_reference(tmp_dir, blend, *jobs):
    """Caches and frames made in one Blender process, as blender_task
    makes them on a farm; each job 'DIR:KEYS:FRAMES'."""
    code, out = pt.run_script(REFERENCE_SCRIPT, tmp_dir, [blend] + list(jobs), name="reference.py", timeout=600)
    assert code == 0, out


@pytest.fixture(scope="module")
def farm_scene(tmp_path_factory):
    """The animation's blend file and its references: frames 1-4 with
    caches made for all four views, frame 1 with caches made for its own."""
    tmp = tmp_path_factory.mktemp("farm")
    pt.enable_addon()
    blend = make_blend(tmp / "walk.blend", 40, 30, 4)
    ref_anim, ref_still = str(tmp / "ref_anim"), str(tmp / "ref_still")
    render_reference(tmp, blend, "%s:1,2,3,4:1,2,3,4" % ref_anim, "%s:1:1" % ref_still)
    return {"tmp": tmp, "blend": blend, "anim": ref_anim, "still": ref_still}


def frame_file(job_dir, f):
    return os.path.join(job_dir, "frames", "frame_%04d.exr" % f)


def check_animation(job_dir, reference):
    """The cache task ran once and every frame loaded its caches; the
    frames are the reference's bit for bit."""
    assert task_state(job_dir, "cache")["attempts"] == 1
    with open(os.path.join(job_dir, "caches", "caches.json")) as f:
        caches = json.load(f)["caches"]
    assert sorted(caches.values()) == ["irradiance.phosirc", "photons.phospmf"]
    for f in FRAMES:
        log = task_log(job_dir, "frame-%d" % f)
        assert "rendering frame %d with irradiance.phosirc, photons.phospmf loaded" % f in log, log[-2000:]
        assert_same_image(frame_file(job_dir, f), frame_file(reference, f))


def check_still(job_dir, reference):
    for i in range(4):
        assert "region %d with irradiance.phosirc, photons.phospmf loaded" % i in task_log(job_dir, "region-1-%d" % i)
    assert_same_image(frame_file(job_dir, 1), frame_file(reference, 1))


# ---------------------------------------------------------------- the job

def test_job_graph_and_its_settings(addon):
    from phos.farm import job as farm_job
    j = farm_job.Job("/s.blend", "/jobs/a", farm_job.parse_frames("1-3"), (1, 1))
    assert [(t.name, t.after) for t in j.tasks()] == [
        ("cache", []), ("frame-1", ["cache"]), ("frame-2", ["cache"]), ("frame-3", ["cache"])]
    assert j.task("cache").args == ["cache", "--job-dir", "/jobs/a", "--frames", "1-3", "--key-frames", "1-3"]
    j = farm_job.Job("/s.blend", "/jobs/b", [5, 6], (2, 2), [5])
    names = [t.name for t in j.tasks()]
    assert names == ["cache"] + ["region-5-%d" % i for i in range(4)] + ["stitch-5"] + \
        ["region-6-%d" % i for i in range(4)] + ["stitch-6"]
    assert j.task("stitch-6").after == ["region-6-%d" % i for i in range(4)]
    assert j.task("region-5-3").args[-6:] == ["--frame", "5", "--region", "3", "--regions", "2x2"]
    assert farm_job.parse_frames(" 7, 1-3,2 ") == [1, 2, 3, 7]
    assert farm_job.format_frames([1, 2, 3, 7, 9, 10]) == "1-3,7,9-10"
    for bad, words in (("3-1", "ends before"), ("1-x", "cannot read"), ("", "none given")):
        with pytest.raises(farm_job.JobError, match=words):
            farm_job.parse_frames(bad)
    with pytest.raises(farm_job.JobError, match="at least one column"):
        farm_job.parse_regions("0x2")
    with pytest.raises(farm_job.JobError, match="not among the frames"):
        farm_job.choose_key_frames([1, 2, 3], "2,9")
    # The borders of a split tile the frame: neighbours share their edge.
    assert farm_job.region_border(0, 2, 2) == (0.0, 0.5, 0.0, 0.5)
    assert farm_job.region_border(3, 2, 2) == (0.5, 1.0, 0.5, 1.0)


def test_bootstrap_is_flamenco_jobs(addon):
    """Flamenco's job type runs the same bootstrap line as the Python side."""
    from phos.farm import job as farm_job
    with open(os.path.join(pt.ADDON_DIR, "phos", "farm", "flamenco", "phos_farm.js")) as f:
        m = re.search(r'^const PHOS_BOOTSTRAP = "(.*)";$', f.read(), re.M)
    assert m and m.group(1) == farm_job.BOOTSTRAP


def test_flamenco_job_type_compiles_under_node():
    node = shutil.which("node") or shutil.which("nodejs")
    if node is None:
        pytest.skip("Node.js is not installed (tools/install-deps.sh --farm installs it)")
    proc = subprocess.run([node, "--test", os.path.join(FARM_DIR, "flamenco_job.test.mjs")],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=120)
    out = proc.stdout.decode("utf-8", "replace")
    assert proc.returncode == 0, out
    assert re.search(r"# pass (\d+)", out) and int(re.search(r"# pass (\d+)", out).group(1)) >= 10, out


def test_bad_submissions_are_refused_clearly(tmp_path, farm_scene):
    code, out = submit(tmp_path, str(tmp_path / "none.blend"), tmp_path / "j", "--frames", "1-4", "--local", "1",
                       check=False)
    assert code == 2 and "no such blend file" in out
    code, out = submit(tmp_path, farm_scene["blend"], tmp_path / "j", "--frames", "1-4", "--key-frames", "7",
                       "--local", "1", check=False)
    assert code == 2 and "not among the frames" in out
    code, out = farm(tmp_path, "status", tmp_path / "nothing", check=False)
    assert code == 2 and "not a farm job folder" in out


# ------------------------------------------------------------ local farm

def test_local_farm_renders_what_one_process_renders(tmp_path, farm_scene):
    anim, still = str(tmp_path / "anim"), str(tmp_path / "still")
    submit(tmp_path, farm_scene["blend"], anim, "--frames", "1-4", "--local", "2")
    check_animation(anim, farm_scene["anim"])
    submit(tmp_path, farm_scene["blend"], still, "--frames", "1", "--regions", "2x2", "--local", "2")
    check_still(still, farm_scene["still"])
    code, out = farm(tmp_path, "status", still)
    assert "6 done" in out


def test_animated_objects_need_caches_per_frame(tmp_path):
    """A box that moves: frames refuse the shared caches, saying so and
    naming --caches per-frame; with it every frame makes its own, and the
    frames are one process's bit for bit."""
    pt.enable_addon()
    blend = make_blend(tmp_path / "moving.blend", 40, 30, 4, box_moves=True)
    ref = str(tmp_path / "ref")
    render_reference(tmp_path, blend, "%s:-:1,4" % ref)
    shared, own = str(tmp_path / "shared"), str(tmp_path / "own")
    code, out = submit(tmp_path, blend, shared, "--frames", "1,4", "--local", "2", check=False)
    assert code == 1, out
    assert task_state(shared, "frame-1")["state"] == "done"   # the cache task's own frame
    error = task_state(shared, "frame-4")["error"]
    assert "made for other geometry" in error and "--caches per-frame" in error, error
    submit(tmp_path, blend, own, "--frames", "1,4", "--caches", "per-frame", "--local", "2")
    assert not os.path.exists(os.path.join(own, "tasks", "cache.json"))
    for f in (1, 4):
        assert "rendering frame %d with caches of its own" % f in task_log(own, "frame-%d" % f)
        assert_same_image(frame_file(own, f), frame_file(ref, f))


def test_farm_panel_submits_a_job(tmp_path, farm_scene, monkeypatch):
    """Render Properties → Phos → Farm: Submit saves the file and runs
    the job (here on this machine); Refresh Status reads its tasks."""
    if not bpy.app.binary_path:
        pytest.skip("Blender as a Python module has no binary for the panel to give the tasks")
    for key, value in _farm_env(tmp_path).items():
        monkeypatch.setenv(key, value)
    blend = str(tmp_path / "panel.blend")
    shutil.copy(farm_scene["blend"], blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    pt.enable_addon()
    s = bpy.context.scene.phos_farm
    s.manager, s.local_processes, s.jobs_folder = 'LOCAL', 2, str(tmp_path / "jobs")
    assert bpy.ops.phos.farm_submit() == {'FINISHED'}
    job_dir = s.last_job
    assert os.path.dirname(job_dir) == str(tmp_path / "jobs")
    end = time.time() + 300
    while time.time() < end:
        bpy.ops.phos.farm_status()
        if s.last_status == "5 done" or "failed" in s.last_status:
            break
        time.sleep(0.5)
    assert s.last_status == "5 done", "%s\n%s" % (s.last_status, open(os.path.join(job_dir, "submit.log")).read())
    check_animation(job_dir, farm_scene["anim"])
    # What the farm cannot render as one machine would is refused with
    # the reason, before anything is written: regions under a noise
    # filter (it reads pixels a region cuts off), two view layers, an
    # unsaved file.
    s.regions, bpy.context.scene.phos.filter = "2x2", 'LOWPASS'
    with pytest.raises(RuntimeError, match="noise filter reads pixels a region cuts off"):
        bpy.ops.phos.farm_submit()
    s.regions, bpy.context.scene.phos.filter = "1x1", 'NONE'
    bpy.context.scene.view_layers.new("Second")
    with pytest.raises(RuntimeError, match="one view layer; this one renders 2"):
        bpy.ops.phos.farm_submit()
    assert sorted(os.listdir(str(tmp_path / "jobs"))) == [os.path.basename(job_dir)]
    pt.reset_file()
    with pytest.raises(RuntimeError, match="save the .blend first"):
        bpy.ops.phos.farm_submit()


def test_stale_cache_is_refused_naming_what_differs(tmp_path, farm_scene):
    """A material changed between the cache task and a frame task: the
    frame task fails with the core's reason, `status` shows it, and after
    the caches are made again the task resubmitted alone succeeds."""
    blend = str(tmp_path / "stale.blend")
    shutil.copy(farm_scene["blend"], blend)
    job_dir = str(tmp_path / "job")
    submit(tmp_path, blend, job_dir, "--frames", "1-2", "--local", "2")
    bpy.ops.wm.open_mainfile(filepath=blend)
    pt.enable_addon()
    mat = bpy.data.materials["Box"]
    mat.node_tree.nodes["Diffuse BSDF"].inputs["Color"].default_value = (0.2, 0.8, 0.3, 1.0)
    bpy.ops.wm.save_mainfile()
    pt.reset_file()
    code, out = farm(tmp_path, "resubmit", job_dir, "frame-2", check=False)
    assert code != 0, out
    state = task_state(job_dir, "frame-2")
    assert state["state"] == "failed" and state["attempts"] == 2
    assert "made for other materials" in state["error"], state
    code, out = farm(tmp_path, "status", job_dir, check=False)
    assert code == 1 and "made for other materials" in out, out
    farm(tmp_path, "resubmit", job_dir, "cache", "frame-2")
    assert task_state(job_dir, "frame-2")["state"] == "done"


# ----------------------------------------------------------------- Slurm

@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    root = tmp_path_factory.mktemp("slurm")
    cluster = slurm_cluster.SlurmCluster(str(root))
    try:
        cluster.start()
    except slurm_cluster.Unavailable as ex:
        cluster.stop()
        pytest.skip("no Slurm cluster on this machine: %s" % ex)
    yield cluster
    cluster.stop()


def wait_for_job(cluster, job_dir, seconds=600):
    assert cluster.wait_idle(seconds), "the Slurm queue did not empty:\n" + cluster.run("squeue")
    states = {n[:-5]: task_state(job_dir, n[:-5])["state"] for n in os.listdir(os.path.join(job_dir, "tasks"))
              if n.endswith(".json")}
    return states


def test_slurm_renders_what_one_process_renders(tmp_path, farm_scene, slurm):
    """The test cluster's MaxArraySize is 3, so the 4 frames and the 4
    regions each go out as two array jobs, as a long job does on a real
    cluster (1001 by default)."""
    env = dict(_farm_env(tmp_path), SLURM_CONF=slurm.conf)
    anim, still = str(tmp_path / "anim"), str(tmp_path / "still")
    code, out = submit(tmp_path, farm_scene["blend"], anim, "--frames", "1-4", env=env)
    assert "submitted to Slurm" in out
    submit(tmp_path, farm_scene["blend"], still, "--frames", "1", "--regions", "2x2", env=env)
    with open(os.path.join(anim, "job.json")) as f:
        assert [part[1:] for part in json.load(f)["manager_ids"]["submitted"]["render"]] == [[0, [0, 1, 2]], [3, [3]]]
    wait_for_job(slurm, anim)
    wait_for_job(slurm, still)
    check_animation(anim, farm_scene["anim"])
    check_still(still, farm_scene["still"])
    code, out = farm(tmp_path, "status", still, env=env)
    assert "6 done" in out, out
    # A task resubmitted alone runs again and writes the same frame.
    farm(tmp_path, "resubmit", anim, "frame-2", env=env)
    wait_for_job(slurm, anim)
    assert task_state(anim, "frame-2")["attempts"] == 2
    assert_same_image(frame_file(anim, 2), frame_file(farm_scene["anim"], 2))


def test_slurm_failed_region_resubmitted_alone(tmp_path, farm_scene, slurm):
    """A region fails (a Blender that refuses it while a flag file
    exists): its frame's stitch fails saying which region is missing,
    the other frame is stitched all the same, and resubmitting the region
    alone brings its stitch along and gives the one-process image."""
    flag = tmp_path / "fail_region"
    flag.write_text("")
    wrapper = tmp_path / "blender.sh"
    wrapper.write_text("#!/bin/sh\ncase \"$*\" in *'--frame 1 --region 0 '*) if [ -e %s ]; then "
                       "echo 'Phos farm: error: refused by the test'; exit 3; fi;; esac\nexec %s \"$@\"\n"
                       % (shlex.quote(str(flag)), shlex.join(pt.BLENDER_COMMAND)))
    wrapper.chmod(0o755)
    env = dict(_farm_env(tmp_path), SLURM_CONF=slurm.conf)
    job_dir = str(tmp_path / "job")
    farm(tmp_path, "submit", farm_scene["blend"], "--job-dir", job_dir, "--blender", str(wrapper), "--frames",
         "1-2", "--regions", "2x2", "--key-frames", "1", env=env)
    wait_for_job(slurm, job_dir)
    assert task_state(job_dir, "region-1-0")["state"] == "failed"
    assert task_state(job_dir, "stitch-2")["state"] == "done"
    stitch = task_state(job_dir, "stitch-1")
    assert stitch["state"] == "failed" and "region 0 of frame 1 is missing" in stitch["error"], stitch
    code, out = farm(tmp_path, "status", job_dir, env=env, check=False)
    assert code == 1 and "refused by the test" in out, out
    flag.unlink()
    code, out = farm(tmp_path, "resubmit", job_dir, "region-1-0", env=env)
    wait_for_job(slurm, job_dir)
    assert task_state(job_dir, "stitch-1")["attempts"] == 2
    code, out = farm(tmp_path, "status", job_dir, env=env)
    assert "11 done" in out, out
    assert_same_image(frame_file(job_dir, 1), frame_file(farm_scene["still"], 1))


def test_python_and_flamenco_build_the_same_tasks(addon):
    """Flamenco's job type and the Python graph give every task the same
    name, arguments and dependencies."""
    node = shutil.which("node") or shutil.which("nodejs")
    if node is None:
        pytest.skip("Node.js is not installed (tools/install-deps.sh --farm installs it)")
    from phos.farm import job as farm_job
    script = """
const fs = require("fs"), vm = require("vm");
const tasks = [];
const author = {
    Task: (name, type) => { const t = {name, cmds: [], deps: []};
        t.addCommand = (c) => t.cmds.push(c); t.addDependency = (d) => t.deps.push(d.name); return t; },
    Command: (type, params) => params,
};
const ctx = {author, print: () => {}};
vm.runInNewContext('"use strict";' + fs.readFileSync(process.argv[1], "utf8") + ";this.compileJob = compileJob;", ctx);
ctx.compileJob({settings: JSON.parse(process.argv[2]), addTask: (t) => tasks.push(t)});
console.log(JSON.stringify(tasks.map((t) => [t.name, t.cmds[0].args.slice(5), t.deps])));
"""
    js = os.path.join(pt.ADDON_DIR, "phos", "farm", "flamenco", "phos_farm.js")
    for frames, regions, keys, caches in (("1-3,7", "1x1", "", "shared"), ("2,5", "2x3", "5", "shared"),
                                          ("1-4", "1x2", "1,3-4", "shared"), ("2-3", "2x1", "", "per-frame"),
                                          ("8", "1x1", "", "per-frame")):
        settings = {"blendfile": "/s.blend", "job_dir": "/jobs/x", "frames": frames, "regions": regions,
                    "key_frames": keys, "caches": caches}
        proc = subprocess.run([node, "-e", script, js, json.dumps(settings)], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, timeout=60)
        assert proc.returncode == 0, proc.stdout.decode()
        fs = farm_job.parse_frames(frames)
        j = farm_job.Job("/s.blend", "/jobs/x", fs, farm_job.parse_regions(regions),
                         farm_job.choose_key_frames(fs, keys), caches=caches)
        assert json.loads(proc.stdout) == [[t.name, t.args, t.after] for t in j.tasks()]


def test_slurm_requeue_of_a_task_killed_mid_render(tmp_path, farm_scene, slurm):
    """`scontrol requeue` kills a frame task while it renders; Slurm runs
    it again and it writes the frame one process renders."""
    blend = make_blend(tmp_path / "slow.blend", 192, 128, 64)
    ref = str(tmp_path / "ref")
    render_reference(tmp_path, blend, "%s:1:1" % ref)
    env = dict(_farm_env(tmp_path), SLURM_CONF=slurm.conf)
    job_dir = str(tmp_path / "job")
    submit(tmp_path, blend, job_dir, "--frames", "1", env=env)
    with open(os.path.join(job_dir, "job.json")) as f:
        render_id = json.load(f)["manager_ids"]["submitted"]["render"][0][0]
    log = os.path.join(job_dir, "logs", "frame-1.log")
    end = time.time() + 300
    while time.time() < end:
        if os.path.exists(log) and "Rendering" in open(log).read():
            break
        time.sleep(0.05)
    else:
        pytest.fail("frame-1 never started rendering")
    element = "%s_0" % render_id
    slurm.run("scontrol", "requeue", element)
    # Slurm holds a requeued job for two minutes before it may start
    # again; once it is pending, let it start now.
    end = time.time() + 60
    while time.time() < end:
        queued = slurm.run("squeue", "-h", "-j", element, "-o", "%T %r").strip()
        if queued.startswith("PENDING") and "BeginTime" in queued:
            slurm.run("scontrol", "update", "JobId=" + element, "StartTime=now")
        elif queued.startswith("RUNNING") or not queued:
            break
        time.sleep(0.2)
    wait_for_job(slurm, job_dir)
    state = task_state(job_dir, "frame-1")
    assert state["state"] == "done" and state["attempts"] == 2 and state["slurm_restart_count"] == 1, state
    first = task_log(job_dir, "frame-1").split("=== attempt 2")[0]
    assert "Rendering" in first and "wrote " not in first, "the first attempt was not killed mid-render"
    assert_same_image(frame_file(job_dir, 1), frame_file(ref, 1))
