# SPDX-License-Identifier: GPL-3.0-or-later
"""python3 -m phos.farm: submit a job, watch it, resubmit failed tasks.

    submit BLEND --frames 1-250 [--regions 2x2] [--key-frames 1,100,200] [--caches per-frame]
           [--job-dir DIR] [--blender PATH] [--blender-args "..."]
           [--local N | --slurm-args='...']
    status JOB_DIR
    resubmit JOB_DIR TASK... [--local N] [--slurm-args='...']
    task JOB_DIR (NAME | --stage S [--offset O] --index I)    one task, as a node runs it
"""

import argparse
import os
import shlex
import sys

from . import local, slurm, status
from .job import CACHES, Job, JobError, choose_key_frames, parse_frames, parse_regions
from .run import run_task, task_state


def _submit(a):
    if not os.path.isfile(a.blend):
        raise JobError("%s: no such blend file" % a.blend)
    frames = parse_frames(a.frames)
    job_dir = a.job_dir or os.path.splitext(os.path.abspath(a.blend))[0] + ".farm"
    exists = os.path.exists(os.path.join(job_dir, "job.json"))
    if exists and not a.overwrite:
        raise JobError("%s already holds a job; give another --job-dir, or --overwrite to replace it" % job_dir)
    job = Job(a.blend, job_dir, frames, parse_regions(a.regions), choose_key_frames(frames, a.key_frames),
              a.blender, shlex.split(a.blender_args), "local" if a.local else "slurm", shlex.split(a.slurm_args),
              caches=a.caches)
    if exists:
        job.clear()
    job.make_folders()
    job.save()
    print("Phos farm: job %s: %d frame(s), regions %dx%d, %s, %d task(s)"
          % (job.job_dir, len(job.frames), job.regions[0], job.regions[1],
             "%d key frame(s)" % len(job.key_frames) if job.caches == "shared" else "caches per frame",
             len(job.tasks())))
    if a.local:
        failed = local.run_local(job, a.local, echo=a.verbose)
        _print_status(job)
        return 1 if failed else 0
    _print_submission("submitted to Slurm", slurm.submit(job))
    print("Phos farm: watch it with: python3 -m phos.farm status %s" % job.job_dir)
    return 0


def _print_submission(what, ids):
    print("Phos farm: %s: %s" % (what, ", ".join(
        "%s %s" % (stage, " ".join(part[0] for part in parts)) for stage, parts in ids.items())))


def _print_status(job):
    rows = status.task_states(job)
    for t, state, record in rows:
        detail = ""
        if record.get("attempts", 0) > 1:
            detail += " attempts %d" % record["attempts"]
        if "seconds" in record:
            detail += " %.1f s" % record["seconds"]
        if record.get("error") and state in ("failed", "killed", "lost"):
            detail += "  " + record["error"]
        print("%-18s %-10s%s" % (t.name, state, detail))
    print("Phos farm: " + status.summary(rows))
    return status.counts(rows)


def _status(a):
    job = Job.load(a.job_dir)
    counts = _print_status(job)
    return 1 if counts.get("failed") or counts.get("lost") else 0


def _resubmit(a):
    job = Job.load(a.job_dir)
    names = job.rerun(a.tasks, done=lambda n: task_state(job, n).get("state") == "done")
    if a.slurm_args is not None:
        job.manager_args = shlex.split(a.slurm_args)
    if a.local or job.manager == "local":
        failed = local.run_tasks(job, names, a.local or 1, echo=a.verbose)
        _print_status(job)
        return 1 if failed else 0
    _print_submission("resubmitted to Slurm", slurm.resubmit(job, names))
    return 0


def _task(a):
    job = Job.load(a.job_dir)
    if a.name:
        name = a.name
    else:
        tasks, index = job.stage_tasks(a.stage), a.offset + a.index
        if not 0 <= index < len(tasks):
            raise JobError("stage %s has no task %d" % (a.stage, index))
        name = tasks[index].name
    return run_task(job, name, echo=sys.stdout.isatty())


def _positive(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError("must be at least 1")
    return value


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m phos.farm", description="Render a Phos job on a farm (docs/farm.md).")
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("submit", help="write a job and run it, on Slurm or --local")
    s.add_argument("blend")
    s.add_argument("--frames", required=True, help="frames to render, e.g. 1-250 or 1-10,20")
    s.add_argument("--regions", default="1x1", help="COLUMNSxROWS regions per frame, stitched after (default 1x1)")
    s.add_argument("--key-frames", default="", help="frames whose views the caches are made for (default: all)")
    s.add_argument("--caches", default="shared", choices=CACHES,
                   help="shared: one cache task for every frame (the camera alone moves); per-frame: each task "
                        "makes its frame's own (objects, lights or materials animate)")
    s.add_argument("--job-dir", help="the job's folder, on storage every node reaches (default: BLEND.farm)")
    s.add_argument("--overwrite", action="store_true", help="replace the job already in --job-dir")
    s.add_argument("--blender", default=os.environ.get("PHOS_FARM_BLENDER", "blender"),
                   help="Blender on the nodes, as a shell reads it (quote a path with spaces; "
                        "default: $PHOS_FARM_BLENDER or blender)")
    s.add_argument("--blender-args", default="", metavar="'ARGS'",
                   help="more Blender arguments, before the blend file, e.g. --blender-args='-y'")
    s.add_argument("--local", type=_positive, default=0, metavar="N", help="run on this machine, N tasks at a time")
    s.add_argument("--slurm-args", default="", metavar="'OPTIONS'",
                   help="more sbatch options for every task, e.g. --slurm-args='-p render -c 8'")
    s.add_argument("-v", "--verbose", action="store_true", help="with --local, show Blender's output")
    st = sub.add_parser("status", help="the state of every task of a job")
    st.add_argument("job_dir")
    r = sub.add_parser("resubmit", help="run failed tasks again, alone")
    r.add_argument("job_dir")
    r.add_argument("tasks", nargs="+")
    r.add_argument("--local", type=_positive, default=0, metavar="N")
    r.add_argument("--slurm-args", default=None, metavar="'OPTIONS'",
                   help="sbatch options for these tasks (default: the job's)")
    r.add_argument("-v", "--verbose", action="store_true")
    t = sub.add_parser("task", help="run one task here (what a node runs)")
    t.add_argument("job_dir")
    t.add_argument("name", nargs="?")
    t.add_argument("--stage", choices=("cache", "render", "stitch"))
    t.add_argument("--index", type=int, default=0, help="the task's index in its stage, less --offset")
    t.add_argument("--offset", type=int, default=0, help="the stage's first task in this array job")
    a = p.parse_args(argv)
    if a.command == "task" and not a.name and not a.stage:
        p.error("task: give a task name, or --stage and --index")
    try:
        return {"submit": _submit, "status": _status, "resubmit": _resubmit, "task": _task}[a.command](a)
    except JobError as ex:
        print("Phos farm: error: %s" % ex, file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
