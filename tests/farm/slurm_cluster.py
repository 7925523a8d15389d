# SPDX-License-Identifier: GPL-3.0-or-later
"""A real single-machine Slurm cluster for the farm's tests: munged,
slurmctld and slurmd on this host, started and stopped as root.

    with SlurmCluster(tmp_dir) as cluster:   # raises Unavailable(reason) if it cannot be
        env = cluster.env                    # SLURM_CONF for sbatch, squeue, scontrol

Everything lives in tmp_dir (configuration, state, spool, logs, munge's
socket), on ports of its own, so it disturbs no cluster this machine may
belong to. Process tracking reads /proc (proctrack/linuxproc) and tasks
are not bound (task/none): no cgroup or systemd is needed, as in a
container. Also runnable by hand: python3 tests/farm/slurm_cluster.py DIR
starts one and waits until interrupted.
"""

import os
import shutil
import signal
import socket
import subprocess
import sys
import time

DAEMONS = ("munged", "slurmctld", "slurmd")
CONTROLLER_PORT, NODE_PORT = 16817, 16818   # not Slurm's defaults (6817, 6818)


class Unavailable(Exception):
    """This machine cannot run the cluster; the message says why."""


def _which_sbin(name):
    return shutil.which(name) or shutil.which(name, path="/usr/sbin:/sbin")


class SlurmCluster:
    def __init__(self, root, cpus=2, max_array_size=3):
        self.root = os.path.abspath(root)
        self.cpus = cpus
        # Small, so that the tests' jobs need several array jobs per stage.
        self.max_array_size = max_array_size
        self.host = socket.gethostname().split(".")[0]
        self.procs = []
        self.conf = os.path.join(self.root, "slurm.conf")
        self.munge_socket = os.path.join(self.root, "munge", "munge.socket")
        self.env = dict(os.environ, SLURM_CONF=self.conf)

    # ------------------------------------------------------------ set-up

    def _check(self):
        if os.geteuid() != 0:
            raise Unavailable("the Slurm test starts munged, slurmctld and slurmd as root; run it as root")
        missing = [d for d in DAEMONS + ("sbatch", "squeue", "scontrol") if not _which_sbin(d)]
        if missing:
            raise Unavailable("Slurm is not installed (missing %s): tools/install-deps.sh --farm installs it"
                              % ", ".join(missing))
        if not os.path.isfile("/etc/munge/munge.key"):
            raise Unavailable("munge has no key (/etc/munge/munge.key): reinstall the munge package")

    def _write_conf(self):
        for sub in ("state", "spool", "log", "munge"):
            os.makedirs(os.path.join(self.root, sub), exist_ok=True)
        r = self.root
        lines = [
            "ClusterName=phostest",
            "SlurmctldHost=%s" % self.host,
            "SlurmctldPort=%d" % CONTROLLER_PORT,
            "SlurmdPort=%d" % NODE_PORT,
            "SlurmUser=root",
            "SlurmdUser=root",
            "AuthType=auth/munge",
            "AuthInfo=socket=%s" % self.munge_socket,
            "StateSaveLocation=%s/state" % r,
            "SlurmdSpoolDir=%s/spool" % r,
            "SlurmctldPidFile=%s/slurmctld.pid" % r,
            "SlurmdPidFile=%s/slurmd.pid" % r,
            "SlurmctldLogFile=%s/log/slurmctld.log" % r,
            "SlurmdLogFile=%s/log/slurmd.log" % r,
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_CPU",
            "SchedulerType=sched/backfill",
            "SchedulerParameters=sched_interval=1",
            "AccountingStorageType=accounting_storage/none",
            "JobAcctGatherType=jobacct_gather/none",
            "JobCompType=jobcomp/none",
            "MpiDefault=none",
            "ReturnToService=2",
            "MinJobAge=600",
            "KillWait=2",
            "MaxArraySize=%d" % self.max_array_size,
            "NodeName=%s CPUs=%d State=UNKNOWN" % (self.host, self.cpus),
            "PartitionName=phostest Nodes=%s Default=YES MaxTime=INFINITE State=UP" % self.host,
        ]
        with open(self.conf, "w") as f:
            f.write("\n".join(lines) + "\n")

    def _start(self, args, name):
        log = open(os.path.join(self.root, "log", name + ".out"), "wb")
        self.procs.append((name, subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=self.env,
                                                  start_new_session=True)))

    def _wait_for(self, what, test, seconds=30.0):
        end = time.time() + seconds
        while time.time() < end:
            for name, p in self.procs:
                if p.poll() is not None:
                    raise Unavailable("%s exited (%d) while starting; see %s/log" % (name, p.returncode, self.root))
            if test():
                return
            time.sleep(0.2)
        raise Unavailable("%s did not come up within %.0f s; see %s/log" % (what, seconds, self.root))

    def _node_idle(self):
        out = subprocess.run(["sinfo", "-h", "-N", "-o", "%t"], capture_output=True, text=True, env=self.env)
        return out.returncode == 0 and out.stdout.strip().startswith("idle")

    def start(self):
        self._check()
        self._write_conf()
        self._start([_which_sbin("munged"), "-F", "--force", "--socket", self.munge_socket,
                     "--pid-file", os.path.join(self.root, "munge", "munged.pid"),
                     "--log-file", os.path.join(self.root, "log", "munged.log"),
                     "--seed-file", os.path.join(self.root, "munge", "munged.seed")], "munged")
        self._wait_for("munged", lambda: os.path.exists(self.munge_socket))
        self._start([_which_sbin("slurmctld"), "-D", "-i", "-f", self.conf], "slurmctld")
        self._wait_for("slurmctld", lambda: subprocess.run(["scontrol", "ping"], capture_output=True,
                                                           env=self.env).returncode == 0)
        self._start([_which_sbin("slurmd"), "-D", "-f", self.conf, "-N", self.host], "slurmd")
        self._wait_for("slurmd", self._node_idle)
        return self

    def stop(self):
        for name, p in reversed(self.procs):
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGTERM)
                except ProcessLookupError:
                    pass
                try:
                    p.wait(10)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()
        self.procs = []

    def __enter__(self):
        try:
            return self.start()
        except BaseException:
            self.stop()
            raise

    def __exit__(self, *exc):
        self.stop()

    # ------------------------------------------------------------- queries

    def run(self, *args):
        """A Slurm command against this cluster; its stdout."""
        out = subprocess.run(list(args), capture_output=True, text=True, env=self.env)
        if out.returncode != 0:
            raise RuntimeError("%s failed: %s" % (" ".join(args), out.stderr.strip()))
        return out.stdout

    def wait_idle(self, seconds):
        """Wait until the queue is empty; False if it is not after `seconds`."""
        end = time.time() + seconds
        while time.time() < end:
            if not self.run("squeue", "-h").strip():
                return True
            time.sleep(0.5)
        return False


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))  # stop the daemons on kill as on Ctrl-C
    with SlurmCluster(sys.argv[1] if len(sys.argv) > 1 else "/tmp/phos-slurm") as c:
        print("Slurm cluster up: export SLURM_CONF=%s  (Ctrl-C stops it)" % c.conf, flush=True)
        try:
            while True:
                time.sleep(3600)
        except (KeyboardInterrupt, SystemExit):
            pass
