"""A throw-away one-node Slurm cluster on 127.0.0.1 for the integration tests.

Debian's ``slurm-wlm`` and ``munge`` (installed with apt when missing and we are root); munged,
slurmctld and slurmd run in the foreground as children of this process, with every file (key,
sockets, config, state, spool, logs) in one temporary folder, and are stopped by their own pids.
No cgroup, accounting or systemd plugin is used.  Clients find the cluster through
``SLURM_CONF`` (:attr:`SlurmCluster.env`).
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
from pathlib import Path

DAEMONS = ("munged", "slurmctld", "slurmd")
CLIENTS = ("sbatch", "squeue", "scontrol", "srun", "sacct")


class SlurmUnavailable(RuntimeError):
    """Slurm cannot be installed or started here (the reason is the message)."""


def _sbin(name: str) -> str | None:
    return shutil.which(name) or shutil.which(name, path="/usr/sbin:/sbin:/usr/local/sbin")


def ensure_installed() -> None:
    """Install ``slurm-wlm`` and ``munge`` with apt-get when a daemon is missing.

    Raises
    ------
    SlurmUnavailable
        When they are missing and cannot be installed (not root, no apt-get, apt failure).
    """
    if all(_sbin(name) for name in (*DAEMONS, "sbatch")):
        return
    if os.geteuid() != 0:
        raise SlurmUnavailable("slurm-wlm/munge are not installed and we are not root")
    if not shutil.which("apt-get"):
        raise SlurmUnavailable("slurm-wlm/munge are not installed and apt-get is unavailable")
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    for command in (
        ["apt-get", "update", "-qq"],
        ["apt-get", "install", "-y", "-qq", "slurm-wlm", "munge"],
    ):
        done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=900)
        if done.returncode:
            raise SlurmUnavailable(
                f"{' '.join(command)} failed ({done.returncode}): {done.stderr[-2000:]}"
            )
    if not all(_sbin(name) for name in (*DAEMONS, "sbatch")):
        raise SlurmUnavailable("slurm-wlm/munge installed, but the daemons are not on PATH")


def _free_ports(count: int) -> list[int]:
    sockets = []
    try:
        for _ in range(count):
            s = socket.socket()
            s.bind(("127.0.0.1", 0))
            sockets.append(s)
        return [s.getsockname()[1] for s in sockets]
    finally:
        for s in sockets:
            s.close()


SLURM_CONF = """\
ClusterName=slipsticktest
SlurmctldHost={node}(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={munge_socket}
StateSaveLocation={root}/state
SlurmdSpoolDir={root}/spool
SlurmctldPidFile={root}/run/slurmctld.pid
SlurmdPidFile={root}/run/slurmd.pid
SlurmctldLogFile={root}/log/slurmctld.log
SlurmdLogFile={root}/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SchedulerParameters=sched_interval=1
MinJobAge=600
KillWait=5
InactiveLimit=0
SlurmdTimeout=60
NodeName={node} NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={memory} State=UNKNOWN
PartitionName=debug Nodes={node} Default=YES MaxTime=INFINITE State=UP
"""


class SlurmCluster:
    """munged + slurmctld + slurmd on 127.0.0.1, configured under ``root``.

    Use :meth:`start` then :meth:`stop` (idempotent; kills only the daemons it started).
    """

    def __init__(self, root: str | Path, cpus: int = 2):
        self.root = Path(root)
        self.cpus = cpus
        self.node = socket.gethostname().split(".")[0]
        self.processes: dict[str, subprocess.Popen] = {}
        self.conf = self.root / "etc" / "slurm.conf"
        self.munge_socket = self.root / "munge" / "munge.socket"

    @property
    def env(self) -> dict[str, str]:
        """Environment for the Slurm clients (sbatch, squeue, ...)."""
        return {**os.environ, "SLURM_CONF": str(self.conf)}

    # -- life cycle ------------------------------------------------------------------------------
    def start(self, timeout: float = 60.0) -> None:
        """Write the configuration and start the daemons; wait until the node is idle."""
        for sub in ("etc", "state", "spool", "run", "log", "munge"):
            (self.root / sub).mkdir(parents=True, exist_ok=True)
        os.chmod(self.root / "munge", 0o700)
        key = self.root / "munge" / "munge.key"
        self._check([_sbin("mungekey"), "--create", f"--keyfile={key}", "--force"], "mungekey")
        os.chmod(key, 0o600)
        ctld_port, slurmd_port = _free_ports(2)
        self.conf.write_text(
            SLURM_CONF.format(
                node=self.node,
                ctld_port=ctld_port,
                slurmd_port=slurmd_port,
                munge_socket=self.munge_socket,
                root=self.root,
                cpus=self.cpus,
                memory=1000,
            )
        )
        self._spawn(
            "munged",
            [
                _sbin("munged"),
                "--foreground",
                "--force",
                f"--key-file={key}",
                f"--socket={self.munge_socket}",
                f"--pid-file={self.root / 'munge' / 'munged.pid'}",
                f"--seed-file={self.root / 'munge' / 'munged.seed'}",
                f"--log-file={self.root / 'log' / 'munged.log'}",
            ],
        )
        self._wait(lambda: self.munge_socket.exists(), 20, "munged socket")
        self._spawn("slurmctld", [_sbin("slurmctld"), "-D", "-i", "-f", str(self.conf)])
        self._wait(lambda: self._run(["scontrol", "ping"]).returncode == 0, timeout, "slurmctld")
        self._spawn("slurmd", [_sbin("slurmd"), "-D", "-N", self.node, "-f", str(self.conf)])

        def idle() -> bool:
            out = self._run(["sinfo", "-h", "-n", self.node, "-o", "%t"]).stdout.strip()
            return out in ("idle", "mix", "alloc")

        self._wait(idle, timeout, "slurmd (node idle)")

    def stop(self) -> None:
        """Stop the daemons this object started (SIGTERM, then SIGKILL), slurmd first."""
        for name in reversed(DAEMONS):
            process = self.processes.pop(name, None)
            if process is None or process.poll() is not None:
                continue
            process.send_signal(signal.SIGTERM)
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(timeout=10)

    # -- jobs ------------------------------------------------------------------------------------
    def sbatch(self, *args: str, cwd=None, env: dict[str, str] | None = None) -> str:
        """Submit with ``sbatch --parsable`` (extra environment ``env``); returns the job id."""
        done = self._run(["sbatch", "--parsable", *args], cwd=cwd, env=env)
        if done.returncode:
            raise RuntimeError(f"sbatch {' '.join(args)} failed: {done.stderr}{self.logs()}")
        return done.stdout.strip().split(";")[0]

    def state(self, job: str) -> str:
        """State of a job (``scontrol show job``), e.g. RUNNING, COMPLETED, FAILED, TIMEOUT."""
        out = self._run(["scontrol", "-o", "show", "job", job]).stdout
        for item in out.split():
            if item.startswith("JobState="):
                return item.split("=", 1)[1]
        return "UNKNOWN"

    def job_info(self, job: str) -> dict[str, str]:
        """``scontrol -o show job`` as a dict (first record)."""
        out = self._run(["scontrol", "-o", "show", "job", job]).stdout.splitlines()
        if not out:
            return {}
        return dict(item.split("=", 1) for item in out[0].split() if "=" in item)

    def wait(self, job: str, timeout: float = 300.0) -> str:
        """Wait until a job (every task of an array) has ended; returns the final state."""
        final = {"COMPLETED", "FAILED", "TIMEOUT", "CANCELLED", "NODE_FAIL", "OUT_OF_MEMORY"}
        final |= {"PREEMPTED", "BOOT_FAIL", "DEADLINE"}
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            out = self._run(["scontrol", "-o", "show", "job", job]).stdout
            states = [item.split("=", 1)[1] for item in out.split() if item.startswith("JobState=")]
            if states and all(s in final for s in states):
                return states[0] if len(set(states)) == 1 else ",".join(states)
            time.sleep(0.5)
        raise TimeoutError(f"job {job} still not done after {timeout:.0f} s{self.logs()}")

    def logs(self) -> str:
        """Tails of the daemon logs (for failure messages)."""
        text = ""
        for path in sorted((self.root / "log").glob("*.log")):
            lines = path.read_text(errors="replace").splitlines()[-15:]
            text += f"\n--- {path.name}\n" + "\n".join(lines)
        return text

    def run(self, command: list[str], cwd=None, env=None) -> subprocess.CompletedProcess:
        """Run a client command (``squeue``, ``slurm/submit.sh``, ...) against this cluster."""
        return self._run(command, cwd=cwd, env=env)

    # -- helpers ---------------------------------------------------------------------------------
    def _run(self, command: list[str], cwd=None, env=None) -> subprocess.CompletedProcess:
        return subprocess.run(
            command,
            env={**self.env, **(env or {})},
            cwd=cwd,
            capture_output=True,
            text=True,
            timeout=60,
        )

    def _check(self, command: list, what: str) -> None:
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
        if done.returncode:
            raise SlurmUnavailable(f"{what} failed: {done.stderr}")

    def _spawn(self, name: str, command: list) -> None:
        log = open(self.root / "log" / f"{name}.stdout", "wb")  # noqa: SIM115 - kept by Popen
        self.processes[name] = subprocess.Popen(
            [str(c) for c in command],
            env=self.env,
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        log.close()

    def _wait(self, ready, timeout: float, what: str) -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for name, process in self.processes.items():
                if process.poll() is not None:
                    raise SlurmUnavailable(
                        f"{name} exited with {process.returncode} while waiting for {what}"
                        f"{self.logs()}"
                    )
            if ready():
                return
            time.sleep(0.3)
        raise SlurmUnavailable(f"timed out waiting for {what}{self.logs()}")
