"""A real single-node Slurm on this machine, for tests and benchmarks of the study's slurm backend.

    with LocalSlurm(folder) as slurm:      # munged, slurmctld and slurmd, as root, all in folder
        os.environ.update(slurm.env)     # SLURM_CONF for sbatch, squeue, sacct
        ...

Everything lives in `folder` (but the daemons' sockets, in a short folder under /tmp): a fresh munge key and socket, slurm.conf (one node: this host with
its cores, one partition "test"), state, spool and logs; the daemons use free TCP ports on
localhost and are stopped (by their pid files) on exit. unavailable() says why it cannot start
(not root, Debian's slurm-wlm or munge missing), else None.
"""
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time

DAEMONS = ("munged", "slurmctld", "slurmd")
CLIENTS = ("sbatch", "squeue", "sinfo")


def unavailable():
    if os.geteuid() != 0:
        return "the local Slurm runs its daemons as root"
    missing = [d for d in DAEMONS + CLIENTS if shutil.which(d) is None and not os.path.exists(f"/usr/sbin/{d}")]
    if missing:
        return f"Slurm is not installed (missing {', '.join(missing)}: apt-get install slurm-wlm munge)"
    return None


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _exe(name):
    return shutil.which(name) or f"/usr/sbin/{name}"


class LocalSlurm:
    def __init__(self, folder, cpus=None):
        self.folder = os.path.abspath(folder)
        self.cpus = cpus or os.cpu_count() or 1
        self.conf = os.path.join(self.folder, "slurm.conf")
        self.env = dict(SLURM_CONF=self.conf)
        self.pids = {d: os.path.join(self.folder, f"{d}.pid") for d in DAEMONS}
        # the daemons' Unix sockets (the spool's, munge's) need a path of at most 107 bytes: a
        # short folder of their own, whatever folder's depth (pytest-xdist's workers add a level)
        self.sockets = None

    def _conf(self, sock):
        d, host = self.folder, socket.gethostname()
        return "\n".join([
            "ClusterName=yadeflextest", "SlurmctldHost=localhost", f"SlurmctldPort={_free_port()}", f"SlurmdPort={_free_port()}",
            "AuthType=auth/munge", "CredType=cred/munge", f"AuthInfo=socket={sock}", "SlurmUser=root", "SlurmdUser=root",
            f"StateSaveLocation={d}/state", f"SlurmdSpoolDir={self.sockets}/spool", f"SlurmctldPidFile={self.pids['slurmctld']}",
            f"SlurmdPidFile={self.pids['slurmd']}", f"SlurmctldLogFile={d}/slurmctld.log", f"SlurmdLogFile={d}/slurmd.log",
            "ProctrackType=proctrack/pgid", "TaskPlugin=task/none", "SwitchType=switch/none", "MpiDefault=none",
            "SchedulerType=sched/builtin", "SelectType=select/cons_tres", "SelectTypeParameters=CR_Core", "ReturnToService=2",
            "AccountingStorageType=accounting_storage/none", "JobAcctGatherType=jobacct_gather/none", "JobCompType=jobcomp/none",
            "PlugStackConfig=/dev/null", "MinJobAge=2",
            f"NodeName={host} NodeAddr=127.0.0.1 CPUs={self.cpus} RealMemory=1000 State=UNKNOWN",
            f"PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP", ""])

    def start(self, timeout=60):
        why = unavailable()
        if why:
            raise RuntimeError(why)
        self.sockets = tempfile.mkdtemp(prefix="yfslurm-", dir="/tmp")
        os.makedirs(os.path.join(self.folder, "state"), exist_ok=True)
        os.makedirs(os.path.join(self.sockets, "spool"), exist_ok=True)
        os.chmod(self.folder, 0o755)  # munged wants its socket's folder searchable by all
        os.chmod(self.sockets, 0o755)
        key = os.path.join(self.folder, "munge.key")
        with open(key, "wb") as fh:
            fh.write(os.urandom(1024))
        os.chmod(key, 0o600)
        sock = os.path.join(self.sockets, "munge.sock")
        subprocess.run([_exe("munged"), "--force", f"--key-file={key}", f"--socket={sock}", f"--pid-file={self.pids['munged']}",
                        f"--log-file={self.folder}/munged.log", f"--seed-file={self.folder}/munged.seed"], check=True, timeout=30)
        with open(self.conf, "w") as fh:
            fh.write(self._conf(sock))
        env = dict(os.environ, **self.env)
        subprocess.run([_exe("slurmctld"), "-f", self.conf], check=True, timeout=30, env=env)
        subprocess.run([_exe("slurmd"), "-f", self.conf], check=True, timeout=30, env=env)
        t0 = time.time()
        while time.time() - t0 < timeout:
            res = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=env, timeout=30)
            if res.returncode == 0 and res.stdout.strip() == "idle":
                return self
            time.sleep(0.5)
        self.stop()
        raise RuntimeError(f"the local Slurm did not come up in {timeout} s (logs in {self.folder})")

    def stop(self):
        for d in reversed(DAEMONS):
            try:
                with open(self.pids[d]) as fh:
                    pid = int(fh.read().strip())
                os.kill(pid, signal.SIGTERM)
            except (OSError, ValueError):
                continue
            for _ in range(100):  # up to 10 s
                try:
                    os.kill(pid, 0)
                except OSError:
                    break
                time.sleep(0.1)
        if self.sockets:
            shutil.rmtree(self.sockets, ignore_errors=True)

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
