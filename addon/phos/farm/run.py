# SPDX-License-Identifier: GPL-3.0-or-later
"""Running one task of a job, the same way under every manager.

run_task starts the task's Blender, appends its output to
logs/NAME.log, and keeps tasks/NAME.json up to date: state (running,
done, failed), attempts, host, exit code, seconds, and the last error
Blender printed. `status` reads these files, so what a task did is
visible whichever manager ran it. A task run again (a requeue, a
resubmission) overwrites its outputs atomically and renders the same
image: renders are deterministic.
"""

import os
import signal
import socket
import subprocess
import sys
import time

from .job import read_json, write_json_atomically

# Lines of a task's output that carry its error: the core's and the add-on's
# reports, and Python's.
ERROR_MARKERS = ("Phos farm: error", "Error:", "Traceback")


def task_state_path(job, name):
    return job.path("tasks", name + ".json")


def task_state(job, name):
    return read_json(task_state_path(job, name), {"state": "waiting", "attempts": 0})


def _threads():
    """The CPUs the manager gave this task (Slurm's --cpus-per-task), so
    that Blender does not start one thread per core of a shared node."""
    value = os.environ.get("SLURM_CPUS_PER_TASK")
    return int(value) if value and value.isdigit() else None


def blender_env():
    """The environment for a task's Blender: this one, less the folder of
    the Python running the farm on PATH, unless it is a system folder. A
    Python launcher (pyenv, an activated venv) puts its own folder first,
    and a Blender linked to the system's Python (Debian's) takes the first
    python3 on PATH for its home: it would then load another Python's
    library and miss numpy."""
    env = dict(os.environ)
    own = os.path.dirname(os.path.abspath(sys.executable)) if sys.executable else ""
    if own and own not in SYSTEM_BIN:
        env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep)
                                      if p and os.path.abspath(p) != own)
    return env


SYSTEM_BIN = ("/usr/bin", "/bin", "/usr/local/bin", "/usr/sbin", "/sbin", "/usr/local/sbin")


def _last_error(log_path, start):
    """The last error line a run wrote to its log (from byte `start`)."""
    try:
        with open(log_path, "rb") as f:
            f.seek(start)
            lines = f.read().decode("utf-8", "replace").splitlines()
    except OSError:
        return ""
    errors = [line.strip() for line in lines if any(m in line for m in ERROR_MARKERS)]
    picked = [e for e in errors if e.startswith("Phos farm: error")] or errors
    return picked[-1] if picked else (lines[-1].strip() if lines else "")


class _Termination:
    """Until Blender has ended: on SIGTERM (Slurm's requeue or time limit,
    scancel) stop it and record the task as killed before exiting, so
    that `status` says what happened. Only in the main thread, where
    Python handles signals; --local runs tasks in worker threads and is
    stopped by Ctrl-C."""

    def __init__(self, job, name, info):
        import threading
        self.job, self.name, self.info, self.proc = job, name, info, None
        self.active = threading.current_thread() is threading.main_thread()
        if self.active:
            self.previous = signal.signal(signal.SIGTERM, self._on_term)

    def _on_term(self, signum, _frame):
        if self.proc is not None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
        write_json_atomically(task_state_path(self.job, self.name),
                              dict(self.info, state="killed", seconds=round(time.time() - self.info["started"], 3),
                                   error="stopped by signal %d (a requeue, time limit or scancel)" % signum))
        sys.exit(128 + signum)

    def close(self):
        if self.active:
            signal.signal(signal.SIGTERM, self.previous)


def run_task(job, name, echo=False):
    """Run task `name` of `job` to its end; its exit code (0: done)."""
    task = job.task(name)
    job.make_folders()
    state = task_state(job, name)
    attempts = state.get("attempts", 0) + 1
    log_path = job.path("logs", name + ".log")
    t0 = time.time()
    info = {"state": "running", "attempts": attempts, "host": socket.gethostname(), "started": t0,
            "slurm_restart_count": int(os.environ.get("SLURM_RESTART_COUNT", "0") or 0)}
    write_json_atomically(task_state_path(job, name), info)
    termination = _Termination(job, name, info)
    try:
        code = _run_blender(job, task, log_path, echo, termination)
    finally:
        termination.close()
    info.update(state="done" if code == 0 else "failed", exit_code=code, seconds=round(time.time() - t0, 3))
    if code != 0:
        info["error"] = _last_error(log_path, info["log_start"])
    del info["log_start"]
    write_json_atomically(task_state_path(job, name), info)
    return code


def _run_blender(job, task, log_path, echo, termination):
    """Run the task's Blender, its output appended to the log; its exit code."""
    info = termination.info
    cmd = job.blender_command(task, _threads())
    with open(log_path, "ab") as log:
        info["log_start"] = log.tell()
        log.write(("\n=== attempt %d on %s: %s\n" % (info["attempts"], info["host"], " ".join(cmd))).encode())
        log.flush()
        try:
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE if echo else log, stderr=subprocess.STDOUT,
                                    stdin=subprocess.DEVNULL, env=blender_env())
        except OSError as ex:
            log.write(("Phos farm: error: cannot start Blender (%s): %s\n" % (job.blender, ex.strerror)).encode())
            code = 127
        else:
            termination.proc = proc
            if echo:
                for line in proc.stdout:
                    log.write(line)
                    sys.stdout.buffer.write(line)
                    sys.stdout.flush()
            code = proc.wait()
    return code
