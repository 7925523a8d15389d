# SPDX-License-Identifier: GPL-3.0-or-later
"""A job on Slurm: sbatch array jobs, stage by stage (docs/farm.md, "Slurm").

    cache    one task
    render   an array job, one element per frame or region, started once
             the cache job succeeded (--dependency=afterok)
    stitch   an array job, one element per split frame, started once the
             render elements have ended (afterany: a stitch whose region
             failed fails itself, saying which, and the other frames'
             stitches still run)

A stage with more tasks than Slurm's MaxArraySize is several array jobs.
Every element runs `python3 -m phos.farm task JOB_DIR --stage S --offset
O --index $SLURM_ARRAY_TASK_ID`, that is run_task on the node, so a Slurm
task does exactly what a local one does. Jobs are submitted with
--requeue: a task killed by a node failure or `scontrol requeue` runs
again and, the render being deterministic, writes the same frame.
"""

import os
import shlex
import subprocess

from . import command
from .job import STAGES, JobError, format_frames


def _slurm(cmd, what):
    """Run a Slurm command; its CompletedProcess. JobError when it cannot start."""
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=False)
    except OSError as ex:
        raise JobError("cannot run %s (%s): is Slurm's client installed on this machine?" % (what, ex.strerror))


def _sbatch(args, script):
    out = _slurm(["sbatch", "--parsable"] + args + [script], "sbatch")
    if out.returncode != 0:
        raise JobError("sbatch refused the job: %s" % (out.stderr.strip() or out.stdout.strip()))
    return out.stdout.strip().split(";")[0]


def _script(job, stage, offset):
    """The batch script of a stage's array job whose element i runs the
    stage's task offset + i (i is 0 for a job that is not an array)."""
    path = job.path("tasks", "slurm-%s-%d.sh" % (stage, offset))
    lines = [
        "#!/bin/sh",
        "# Phos farm: stage '%s' of %s (written by python3 -m %s submit)" % (stage, job.blend_file, command.MODULE),
        "export PYTHONPATH=%s${PYTHONPATH:+:$PYTHONPATH}" % shlex.quote(command.PACKAGE_PARENT),
        "exec %s -m %s task %s --stage %s --offset %d --index \"${SLURM_ARRAY_TASK_ID:-0}\""
        % (shlex.quote(command.python()), command.MODULE, shlex.quote(job.job_dir), stage, offset),
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.chmod(path, 0o755)
    return path


def max_array_size():
    """Slurm's MaxArraySize: array indices run from 0 to one less (1001
    by default, so a 300-frame job of 2 × 2 regions needs two arrays)."""
    out = _slurm(["scontrol", "show", "config"], "scontrol")
    for line in out.stdout.splitlines():
        key, _, value = line.partition("=")
        if key.strip() == "MaxArraySize" and value.strip().isdigit():
            return max(1, int(value.strip()))
    return 1001


def _common_args(job, stage, array):
    output = "slurm-%s-%%A_%%a.out" % stage if array else "slurm-%s-%%j.out" % stage
    return (["--job-name", "phos-%s-%s" % (os.path.splitext(os.path.basename(job.blend_file))[0], stage),
             "--output", job.path("logs", output), "--requeue", "--chdir", job.job_dir] + list(job.manager_args))


DEPENDENCY = {"render": "afterok", "stitch": "afterany"}


def _submit_stages(job, names):
    """Submit tasks `names`, stage by stage, each stage's as array jobs of
    at most MaxArraySize elements over its stage indices, each waiting
    for the stage before it among them. Returns {stage: [[job id, offset,
    [stage indices]], …]}; on a refusal, cancels what it submitted."""
    chunk, wanted = max_array_size(), set(names)
    ids, after = {}, []
    try:
        for stage in STAGES:
            indices = [i for i, t in enumerate(job.stage_tasks(stage)) if t.name in wanted]
            if not indices:
                continue
            parts = []
            for offset in sorted({i // chunk * chunk for i in indices}):
                elements = [i - offset for i in indices if offset <= i < offset + chunk]
                args = _common_args(job, stage, stage != "cache")
                if stage != "cache":
                    args += ["--array", format_frames(elements)]  # Slurm's syntax: 0-2,5
                if after:
                    args += ["--dependency", "%s:%s" % (DEPENDENCY[stage], ":".join(after))]
                parts.append([_sbatch(args, _script(job, stage, offset)), offset, [offset + e for e in elements]])
            ids[stage] = parts
            after = [p[0] for p in parts]
    except JobError:
        submitted = [p[0] for parts in ids.values() for p in parts]
        if submitted:
            _slurm(["scancel"] + submitted, "scancel")
        raise
    return ids


def submit(job):
    """Submit every task; job.manager_ids records the array jobs."""
    job.manager = "slurm"
    job.manager_ids = {"submitted": _submit_stages(job, [t.name for t in job.tasks()])}
    job.save()
    return job.manager_ids["submitted"]


def resubmit(job, names):
    """Submit tasks `names` again (Job.rerun says which) as array jobs of
    their own. Elements still pending that can never start (their
    dependency failed) are cancelled first: the resubmission runs them."""
    _cancel_never_starting(job)
    ids = _submit_stages(job, names)
    job.manager_ids.setdefault("resubmitted", []).append(ids)
    job.save()
    return ids


def _cancel_never_starting(job):
    for job_id, _index, state, reason in _queue(job):
        if state == "PENDING" and "DependencyNeverSatisfied" in reason:
            _slurm(["scancel", job_id], "scancel")


def _array_jobs(job):
    """Slurm job id → {array index: task name} for every submission of the job."""
    submissions = [job.manager_ids.get("submitted", {})] + list(job.manager_ids.get("resubmitted", []))
    by_id = {}
    for submission in submissions:
        for stage, parts in submission.items():
            tasks = job.stage_tasks(stage)
            for job_id, offset, indices in parts:
                by_id[job_id] = {i - offset: tasks[i].name for i in indices if i < len(tasks)}
    return by_id


def _queue(job):
    """(job id with array index, index, state, reason) of this job's
    queued and running elements, from squeue."""
    ids = list(_array_jobs(job))
    if not ids:
        return []
    out = _slurm(["squeue", "-h", "-r", "-j", ",".join(ids), "-o", "%i|%K|%T|%r"], "squeue")
    return [tuple(line.split("|")) for line in out.stdout.splitlines() if line.count("|") == 3]


def queued_states(job):
    """Task name → Slurm state (PENDING, RUNNING, …, with the reason) of
    the elements still in the queue."""
    by_id = _array_jobs(job)
    states = {}
    for job_id, index, state, reason in _queue(job):
        names = by_id.get(job_id.split("_")[0], {})
        name = names.get(int(index) if index.isdigit() else 0)
        if name:
            states[name] = state + (" (%s)" % reason if reason and reason != "None" else "")
    return states

