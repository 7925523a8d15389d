# SPDX-License-Identifier: GPL-3.0-or-later
"""The state of a job's tasks, for `status` and the Farm panel.

A task's own file (tasks/NAME.json, run.py) says what it last did:
running, done, failed or killed. On Slurm the queue says more about what
is not finished: pending (and why), or running again after a requeue. A
task whose file says running but which Slurm no longer holds was killed
without a chance to record it (SIGKILL, out of memory, a lost node): it
is `lost`, and resubmitting it runs it again.
"""

from . import slurm
from .run import task_state


def task_states(job):
    """(task, state, its file's record) for every task of the job, in order."""
    queued = slurm.queued_states(job) if job.manager == "slurm" else None
    rows = []
    for t in job.tasks():
        record = task_state(job, t.name)
        state = record.get("state", "waiting")
        if queued is not None and state not in ("done",):
            if t.name in queued:
                state = queued[t.name].lower()
            elif state == "running":
                state = "lost"
        rows.append((t, state, record))
    return rows


def counts(rows):
    """'5 done, 2 pending (dependency)' → {'done': 5, 'pending': 2}."""
    out = {}
    for _t, state, _record in rows:
        key = state.split()[0]
        out[key] = out.get(key, 0) + 1
    return out


def summary(rows):
    return ", ".join("%d %s" % (n, s) for s, n in sorted(counts(rows).items()))
