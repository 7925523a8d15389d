# SPDX-License-Identifier: GPL-3.0-or-later
"""A job on this machine: its tasks on N processes at a time, each run
by run_task as a farm's node runs it, each started once every task it
waits for is done. A failed task fails the tasks that wait for it;
the others go on, and `resubmit` runs the failed ones again."""

import concurrent.futures

from .run import run_task


def run_local(job, processes, echo=False):
    """Run every task of `job`; the names of those that failed or could
    not run, in the job's order."""
    return run_tasks(job, [t.name for t in job.tasks()], processes, echo)


def run_tasks(job, names, processes, echo=False):
    """Run tasks `names` of `job` (a task waits only for those of its
    dependencies that are among them); the names that did not finish."""
    todo = {t.name: t for t in job.tasks() if t.name in set(names)}
    done, failed, running = set(), set(), {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, processes)) as pool:
        while todo or running:
            for name in list(todo):
                waits = [a for a in todo[name].after if a in todo or a in running or a in failed]
                if any(a in failed for a in waits):
                    failed.add(name)
                    del todo[name]
                elif not waits and len(running) < processes:
                    running[name] = pool.submit(run_task, job, name, echo)
                    del todo[name]
            if not running:
                break
            finished, _ = concurrent.futures.wait(running.values(), return_when=concurrent.futures.FIRST_COMPLETED)
            for name, future in list(running.items()):
                if future in finished:
                    (done if future.result() == 0 else failed).add(name)
                    del running[name]
    return [t.name for t in job.tasks() if t.name in failed]
