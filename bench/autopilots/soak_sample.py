#!/usr/bin/env python3
"""Every PERIOD_S, the resident memory of the run RUN_PID and of every process in the cgroups of
scenario NAME's robots (any hierarchy's <mount>/sitlnet/NAME/<robot>/cgroup.procs), as CSV on
stdout: wall_s,robot,pid,comm,rss_kib ("sitlnet" for the run itself). Ends with the run.

  soak_sample.py RUN_PID NAME PERIOD_S
"""
import glob
import os
import sys
import time


def rss_kib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def comm(pid):
    try:
        with open(f"/proc/{pid}/comm") as f:
            return f.read().strip()
    except OSError:
        return "?"


def main():
    run_pid, name, period_s = int(sys.argv[1]), sys.argv[2], float(sys.argv[3])
    start = time.monotonic()
    print("wall_s,robot,pid,comm,rss_kib", flush=True)
    while os.path.exists(f"/proc/{run_pid}"):
        now = time.monotonic() - start
        rows = {("sitlnet", run_pid)}
        for procs in glob.glob(f"/sys/fs/cgroup/**/sitlnet/{name}/*/cgroup.procs", recursive=True):
            robot = os.path.basename(os.path.dirname(procs))
            try:
                with open(procs) as f:
                    rows |= {(robot, int(p)) for p in f.read().split()}
            except OSError:
                continue
        for robot, pid in sorted(rows):
            rss = rss_kib(pid)
            if rss is not None:
                print(f"{now:.0f},{robot},{pid},{comm(pid)},{rss}", flush=True)
        time.sleep(period_s)


if __name__ == "__main__":
    main()
