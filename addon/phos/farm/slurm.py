# SPDX-License-Identifier: GPL-3.0-or-later
"""A job on Slurm: one sbatch job per stage (docs/farm.md, "Slurm").

    cache    one task
    render   an array job, one element per frame or region, after the
             cache job succeeded (--dependency=afterok)
    stitch   an array job, one element per split frame, after the render
             array succeeded

A stage with more tasks than Slurm's MaxArraySize is several array jobs.
Every element runs `python3 -m phos.farm task JOB_DIR --stage S --offset
O --index $SLURM_ARRAY_TASK_ID`, that is run_task on the node, so a Slurm task
does exactly what a local one does. Jobs are submitted with --requeue: a
task killed by a node failure or `scontrol requeue` runs again and, the
render being deterministic, writes the same frame. State comes from the
task files (run.py), and from squeue for what has not started.
"""

import os
import shlex
import subprocess
import sys

from .job import JobError

# The folder holding the `phos` package, for the nodes' PYTHONPATH.
PACKAGE_PARENT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PACKAGE = __package__.rsplit(".", 1)[0]   # "phos", or the extension's full name


def _sbatch(args, script):
    cmd = ["sbatch", "--parsable"] + args + [script]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, check=False)
    except OSError as ex:
        raise JobError("cannot run sbatch (%s): is Slurm's client installed here?" % ex.strerror)
    if out.returncode != 0:
        raise JobError("sbatch refused the job: %s" % (out.stderr.strip() or out.stdout.strip()))
    return out.stdout.strip().split(";")[0]


def _script(job, stage, offset):
    """The batch script of a stage's array job whose element i runs the
    stage's task offset + i (i is 0 for a job that is not an array)."""
    path = job.path("tasks", "slurm-%s-%d.sh" % (stage, offset))
    lines = [
        "#!/bin/sh",
        "# Phos farm: stage '%s' of %s (written by python3 -m %s.farm submit)" % (stage, job.blend_file, PACKAGE),
        "export PYTHONPATH=%s${PYTHONPATH:+:$PYTHONPATH}" % shlex.quote(PACKAGE_PARENT),
        "exec %s -m %s.farm task %s --stage %s --offset %d --index \"${SLURM_ARRAY_TASK_ID:-0}\""
        % (shlex.quote(sys.executable), PACKAGE, shlex.quote(job.job_dir), stage, offset),
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.chmod(path, 0o755)
    return path


def max_array_size():
    """Slurm's MaxArraySize: array indices run from 0 to one less (1001
    by default, so a 250-frame job of 2 × 2 regions needs two arrays)."""
    out = subprocess.run(["scontrol", "show", "config"], capture_output=True, text=True, check=False)
    for line in out.stdout.splitlines():
        key, _, value = line.partition("=")
        if key.strip() == "MaxArraySize" and value.strip().isdigit():
            return max(1, int(value.strip()))
    return 1001


def _common_args(job, stage, slurm_args, array):
    output = "slurm-%s-%%A_%%a.out" % stage if array else "slurm-%s-%%j.out" % stage
    return (["--job-name", "phos-%s-%s" % (os.path.splitext(os.path.basename(job.blend_file))[0], stage),
             "--output", job.path("logs", output), "--requeue", "--chdir", job.job_dir] + list(slurm_args))


def submit(job, slurm_args=()):
    """Submit the job's stages; job.manager_ids gets their Slurm job ids:
    the cache job's, then per array stage [job id, first task, tasks] of
    each of its array jobs (more than one when a stage has more tasks
    than Slurm's MaxArraySize)."""
    ids, after, chunk = {}, [], max_array_size()
    for stage in ("cache", "render", "stitch"):
        tasks = job.stage_tasks(stage)
        if not tasks:
            continue
        parts = []
        for offset in range(0, len(tasks), chunk):
            count = min(chunk, len(tasks) - offset)
            array = stage != "cache"
            args = _common_args(job, stage, slurm_args, array)
            if array:
                args += ["--array", "0-%d" % (count - 1)]
            if after:
                args += ["--dependency", "afterok:" + ":".join(after)]
            parts.append([_sbatch(args, _script(job, stage, offset)), offset, count])
        ids[stage] = parts[0][0] if stage == "cache" else parts
        after = [p[0] for p in parts]
    job.manager, job.manager_ids = "slurm", ids
    job.save()
    return ids


def resubmit(job, names, slurm_args=()):
    """Submit the tasks `names` again, each alone (their caches exist),
    with the stitch of any region among them after it (Job.rerun); pending elements
    that waited for them are cancelled first, since Slurm never starts
    an element whose dependency failed."""
    names = job.rerun(names)
    _cancel_pending(job)
    ids = {}
    for name in names:
        task = job.task(name)
        index = [t.name for t in job.stage_tasks(task.stage)].index(name)
        args = _common_args(job, task.stage, slurm_args, True) + ["--array", "0"]
        waits = [ids[a] for a in task.after if a in ids]
        if waits:
            args += ["--dependency", "afterok:" + ":".join(waits)]
        ids[name] = _sbatch(args, _script(job, task.stage, index))
    job.manager_ids.setdefault("resubmitted", {}).update(ids)
    job.save()
    return ids


def _cancel_pending(job):
    """Cancel this job's elements that can never start (their dependency failed)."""
    for job_id, _index, state, reason in _queue(job):
        if state == "PENDING" and "DependencyNeverSatisfied" in reason:
            subprocess.run(["scancel", job_id], capture_output=True, check=False)


def _array_jobs(job):
    """Slurm job id → the tasks its elements run, in index order."""
    by_id = {}
    for stage, entry in job.manager_ids.items():
        if stage == "cache":
            by_id[entry] = job.stage_tasks("cache")
        elif stage in ("render", "stitch"):
            tasks = job.stage_tasks(stage)
            for job_id, offset, count in entry:
                by_id[job_id] = tasks[offset:offset + count]
    for name, job_id in job.manager_ids.get("resubmitted", {}).items():
        by_id[job_id] = [job.task(name)]
    return by_id


def _queue(job):
    """(job id with array index, index, state, reason) of this job's
    queued and running elements, from squeue."""
    ids = list(_array_jobs(job))
    if not ids:
        return []
    out = subprocess.run(["squeue", "-h", "-r", "-j", ",".join(ids), "-o", "%i|%K|%T|%r"],
                         capture_output=True, text=True, check=False)
    rows = []
    for line in out.stdout.splitlines():
        parts = line.split("|")
        if len(parts) == 4:
            rows.append(tuple(parts))
    return rows


def queued_states(job):
    """Task name → Slurm state (PENDING, RUNNING, …) for the elements
    still in the queue."""
    by_id = _array_jobs(job)
    states = {}
    for job_id, index, state, reason in _queue(job):
        tasks = by_id.get(job_id.split("_")[0])
        if not tasks:
            continue
        i = int(index) if index.isdigit() else 0
        if i >= len(tasks):
            continue
        states[tasks[i].name] = state + (" (%s)" % reason if reason and reason != "None" else "")
    return states
