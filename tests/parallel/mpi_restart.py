#!/usr/bin/env python3
"""Restarts of distributed runs (ctest `mpi_restart`, FIBRANE_PETSC builds only).

On the peeling example at the coarse mesh of mpi_history.py (arc-length, checkpoint after every step):
  reference     mpiexec -n 2 fibrane run CASE, uninterrupted
  kill -9       every process of a 2-process run (mpiexec and both ranks) killed by SIGKILL once history.csv
                has ROWS rows; `mpiexec -n 2 fibrane run CASE --restart DIR` continues it: its history
                equals the reference's to 1e-10 (relative to each column's largest magnitude), the same
                steps and Newton iterations
  other count   a copy of the killed run's directory continued by one process (`fibrane run CASE --restart`,
                the case's serial solver): agrees with the reference to 1e-8, the Newton tolerance's
                level that mpi_history.py holds the serial and distributed runs to
  SIGTERM       a 2-process run with checkpoint_every 0, SIGTERM to both ranks (as a batch system at its
                time limit): both exit with 143, summary.json says interrupted by SIGTERM, the checkpoint
                of the last step is there; `mpiexec -n 2 ... --restart` ends equal to the reference (1e-10)
  one process   SIGTERM to rank 1 only: rank 0 stops after the same step (the processes decide together),
                the checkpoint and summary.json are written
and on the bending example at the coarse mesh of mpi_history.py (load stepping with Newton's local first
updates): the kill -9 of a 2-process run and its restart on 2 processes, which makes local updates and
ends equal to its uninterrupted run to 1e-10 (two uninterrupted 2-process runs of this case differ by
~4e-12, with or without the local updates, where the peeling example's are the same bits).
Exit 0 when all hold, 1 with the failures listed otherwise.
"""
import json
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

from mpi_common import case_text, compare, driver_arguments, mpi_environment, read_history, run

ROWS = 6  # history rows (the initial state and 5 steps) before a run is interrupted
SAME_COUNT, OTHER_COUNT = 1e-10, 1e-8


def processes(directory):
    """{rank: pid} of the fibrane processes (and `mpiexec`: rank -1) whose command line names `directory`."""
    found = {}
    for entry in pathlib.Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            argv = (entry / "cmdline").read_bytes().split(b"\0")
            environ = (entry / "environ").read_bytes().split(b"\0")
        except OSError:
            continue
        if str(directory).encode() not in argv:
            continue
        rank = -1
        for item in environ:
            if item.startswith(b"OMPI_COMM_WORLD_RANK="):
                rank = int(item.split(b"=", 1)[1])
        found.setdefault(rank, []).append(int(entry.name))
    return found


def start_and_wait_for_rows(command, directory, log):
    """Starts `command` and returns it once `directory`/history.csv has ROWS rows (fails if it ends first)."""
    out = open(log, "w")
    proc = subprocess.Popen(command, env=mpi_environment(), stdout=out, stderr=subprocess.STDOUT)
    history = directory / "history.csv"
    while True:
        if proc.poll() is not None:
            raise SystemExit(f"mpi_restart: {' '.join(map(str, command))} ended (exit {proc.returncode}) before "
                             f"{ROWS} history rows; the case must run longer:\n{pathlib.Path(log).read_text()}")
        if history.exists() and len(history.read_text().splitlines()) - 1 >= ROWS:
            return proc
        time.sleep(0.01)


def signal_ranks(directory, ranks, sig):
    pids = processes(directory)
    for rank in ranks:
        for pid in pids.get(rank, []):
            os.kill(pid, sig)


def main():
    a, fibrane, work = driver_arguments(__doc__.splitlines()[0])
    text = case_text(a.examples.resolve(), "peeling")
    case = work / "peeling.yaml"
    case.write_text(text)
    quiet_case = work / "peeling-term.yaml"  # checkpoints only when interrupted
    quiet_case.write_text(text.replace("output: {vtk: false}", "output: {vtk: false, checkpoint_every: 0}"))
    mpi2 = [a.mpiexec, "-n", "2", fibrane, "run"]
    problems = []

    def check(label, directory, reference, tolerance):
        problems.extend(compare(reference, read_history(directory / "history.csv"), label, tolerance))

    run(mpi2 + [case, "-q", "-o", work / "reference"], work, work / "reference.log")
    reference = read_history(work / "reference" / "history.csv")

    def kill(case_file, killed):
        """A 2-process run of `case_file` into `killed`, killed by SIGKILL (mpiexec and both ranks) mid-run."""
        proc = start_and_wait_for_rows(mpi2 + [case_file, "-q", "-o", killed], killed, work / f"{killed.name}.log")
        signal_ranks(killed, [-1, 0, 1], signal.SIGKILL)
        proc.wait()
        if (killed / "summary.json").exists():
            problems.append(f"kill -9 of {killed.name}: the killed run wrote summary.json (it was not killed mid-run)")

    # kill -9 of everything the run consists of, then restarts on 2 and on 1 process.
    killed = work / "killed"
    kill(case, killed)
    shutil.copytree(killed, work / "killed-np1")
    run(mpi2 + [case, "-q", "--restart", killed], work, work / "killed-restart.log")
    check("kill -9, restart on 2 processes", killed, reference, SAME_COUNT)
    run([fibrane, "run", case, "-q", "--restart", work / "killed-np1"], work, work / "killed-np1.log")
    check("kill -9, restart on 1 process", work / "killed-np1", reference, OTHER_COUNT)

    # The same on the bending example, whose steps begin with a local update on the processes together.
    bending = work / "bending.yaml"
    bending.write_text(case_text(a.examples.resolve(), "bending"))
    run(mpi2 + [bending, "-q", "-o", work / "bending-reference"], work, work / "bending-reference.log")
    bending_killed = work / "bending-killed"
    kill(bending, bending_killed)
    run(mpi2 + [bending, "-q", "--restart", bending_killed], work, work / "bending-killed-restart.log")
    check("bending, kill -9, restart on 2 processes", bending_killed,
          read_history(work / "bending-reference" / "history.csv"), SAME_COUNT)
    restarted = json.loads((bending_killed / "summary.json").read_text())
    if restarted["local_updates"] == 0:  # counted since the checkpoint
        problems.append("bending, kill -9, restart on 2 processes: the restarted run made no local update")

    # SIGTERM to every rank, and to rank 1 alone.
    for label, ranks in (("SIGTERM to both", [0, 1]), ("SIGTERM to rank 1", [1])):
        directory = work / label.replace(" ", "-")
        proc = start_and_wait_for_rows(mpi2 + [quiet_case, "-q", "-o", directory], directory, work / f"{directory.name}.log")
        signal_ranks(directory, ranks, signal.SIGTERM)
        code = proc.wait()
        summary = json.loads((directory / "summary.json").read_text())
        rows = len(read_history(directory / "history.csv")["step"])
        print(f"{label}: mpiexec exit {code}, outcome {summary['outcome']}, {summary.get('interrupted')}, "
              f"{rows} rows, checkpoints {summary['checkpoints']['written']}")
        if code == 0 or summary["outcome"] != "interrupted" or summary.get("interrupted") != "SIGTERM":
            problems.append(f"{label}: not ended as interrupted by SIGTERM (exit {code}, {summary['outcome']})")
        if not (directory / "checkpoint.bin").exists() or summary["checkpoints"]["written"] != 1:
            problems.append(f"{label}: no checkpoint written at the interruption")
        if rows >= len(reference["step"]):
            problems.append(f"{label}: the run reached its end; the signal came too late to test anything")
        run(mpi2 + [quiet_case, "-q", "--restart", directory], work, work / f"{directory.name}-restart.log")
        check(f"{label}, restart on 2 processes", directory, reference, SAME_COUNT)
    for line in problems:
        print(line)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
