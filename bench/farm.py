# SPDX-License-Identifier: GPL-3.0-or-later
"""What a farm's cache task saves: a walkthrough rendered frame by frame
with caches of its own, against the same frames reading one cache task's
photon maps and irradiance cache (docs/farm.md, "Measured").

    python3 bench/farm.py [--frames N] [--resolution W H] [--samples S] [--out DIR]
                          [--slurm]   (also on the Slurm cluster of $SLURM_CONF)

The Cornell box of scenes/cornell_box.py (PHOTON with the irradiance
cache, its defaults), its camera dollying in over N frames. Rows:

- one Blender process renders every frame, each tracing its photons and
  filling its cache (`blender -b -a`, what a user without a farm does);
- the farm's tasks on this machine one at a time (`--local 1`): the cache
  task, then every frame loading its caches, each a Blender of its own;
- with --slurm, the same job through sbatch, one task at a time with
  every core (-c of this machine's cores).

Times are wall seconds; the tasks' own come from their state files
(farm/run.py). Frames of one job run one after another, so the sums are
a single node's; on a farm the frames spread over its nodes.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "addon"))
from phos.farm.run import blender_env  # noqa: E402  (Blender as the farm starts it)
ANIMATE = """
import bpy, sys
scene = bpy.context.scene
cam = scene.camera
n = int(sys.argv[-2])
scene.frame_start, scene.frame_end = 1, n
start = cam.location.copy()
cam.keyframe_insert("location", frame=1)
cam.location = start * 0.8 + cam.matrix_world.to_3x3().col[0] * 0.3
cam.keyframe_insert("location", frame=n)
scene.render.image_settings.file_format = 'OPEN_EXR'
bpy.ops.wm.save_mainfile(filepath=sys.argv[-1])
"""


def run(cmd, env=None, **kw):
    env = env or blender_env()
    t0 = time.perf_counter()
    out = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, **kw)
    text = out.stdout.decode("utf-8", "replace")
    if out.returncode != 0:
        sys.exit("bench/farm.py: %s failed:\n%s" % (" ".join(cmd[:4]), text[-3000:]))
    return time.perf_counter() - t0, text


def build(out, frames, resolution, samples):
    blend = os.path.join(out, "walk.blend")
    # --python-exit-code: a script that raises would otherwise leave Blender's
    # exit status 0, and the run render Blender's default 250 frames.
    run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
         os.path.join(REPO, "scenes", "cornell_box.py"), "--",
         "--save", blend, "--resolution", str(resolution[0]), str(resolution[1]), "--samples", str(samples)])
    script = os.path.join(out, "animate.py")
    with open(script, "w") as f:
        f.write(ANIMATE)
    run(["blender", "-b", blend, "--python-exit-code", "1", "--python", script, "--", str(frames), blend])
    return blend


def farm_env(out):
    scripts = os.path.join(out, "user_scripts")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "phos")
    if not os.path.lexists(link):
        os.symlink(os.path.join(REPO, "addon", "phos"), link)
    return dict(os.environ, PYTHONPATH=os.path.join(REPO, "addon"), BLENDER_USER_SCRIPTS=scripts)


def task_seconds(job_dir):
    out = {}
    for name in os.listdir(os.path.join(job_dir, "tasks")):
        if name.endswith(".json"):
            with open(os.path.join(job_dir, "tasks", name)) as f:
                out[name[:-5]] = json.load(f).get("seconds", float("nan"))
    return out


def stage_seconds(log_text):
    """Phos's own stage times of each render in a Blender log, summed."""
    sums = {}
    for line in log_text.splitlines():
        if line.startswith("Phos: exporting and building the BVH"):
            for name, secs in re.findall(r"([a-z][a-z -]+?) ([0-9.]+) s", line.split(";")[0][len("Phos: "):]):
                sums[name.strip()] = sums.get(name.strip(), 0.0) + float(secs)
    return sums


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--frames", type=int, default=8)
    p.add_argument("--resolution", type=int, nargs=2, default=(320, 320))
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--out", default=os.path.join(REPO, "build", "bench-farm"))
    p.add_argument("--slurm", action="store_true")
    a = p.parse_args()
    # Absolute: Blender's save operator refuses a relative path, and the
    # Makefile passes one (out/bench/farm).
    a.out = os.path.abspath(a.out)
    os.makedirs(a.out, exist_ok=True)
    blend = build(a.out, a.frames, a.resolution, a.samples)
    env = farm_env(a.out)
    n = a.frames

    plain_env = dict(blender_env(), BLENDER_USER_SCRIPTS=env["BLENDER_USER_SCRIPTS"])
    t_plain, log = run(["blender", "-b", "--addons", "phos", blend, "-o", os.path.join(a.out, "plain", "frame_####"),
                        "-a"], env=plain_env)
    if "Phos: exporting" not in log:
        sys.exit("bench/farm.py: the plain render did not render with Phos:\n" + log[-2000:])
    plain_stages = stage_seconds(log)

    rows = [("one process, each frame its own caches", t_plain, t_plain / n, "")]
    for manager in ["local"] + (["slurm"] if a.slurm else []):
        job_dir = os.path.join(a.out, "job_" + manager)
        args = [sys.executable, "-m", "phos.farm", "submit", blend, "--frames", "1-%d" % n, "--job-dir", job_dir,
                "--overwrite"]
        args += ["--local", "1"] if manager == "local" else ["--slurm-args", "-c %d" % os.cpu_count()]
        t_job, text = run(args, env=env)
        if manager == "slurm":
            while subprocess.run(["squeue", "-h"], capture_output=True, text=True, env=env).stdout.strip():
                time.sleep(0.5)
            t_job = None
        secs = task_seconds(job_dir)
        frame_secs = [secs["frame-%d" % f] for f in range(1, n + 1)]
        total = secs["cache"] + sum(frame_secs)
        rows.append(("farm (%s): cache task" % manager, secs["cache"], None, ""))
        rows.append(("farm (%s): frame tasks" % manager, sum(frame_secs), sum(frame_secs) / n,
                     "cache + frames %.1f s%s" % (total, "" if t_job is None else ", wall %.1f s" % t_job)))

    print("\n%d frames of the Cornell box, %d x %d, %d samples, PHOTON with the irradiance cache"
          % (n, a.resolution[0], a.resolution[1], a.samples))
    print("| run | seconds | per frame | |\n|---|---|---|---|")
    for name, secs, per, note in rows:
        print("| %s | %.1f | %s | %s |" % (name, secs, "" if per is None else "%.2f" % per, note))
    print("\none process, Phos's stages summed over the frames: "
          + ", ".join("%s %.1f s" % kv for kv in plain_stages.items()))


if __name__ == "__main__":
    main()
