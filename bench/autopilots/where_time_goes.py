#!/usr/bin/env python3
"""Where the wall time of an idle lockstep fleet of real autopilots goes (issue 46, item 1).

  where_time_goes.py SITLNET SCENARIO OUT_DIR VIRTUAL_S KIND N LOAD1

Runs `SITLNET run SCENARIO --out OUT_DIR/run` with its progress line on (to a file, one line
every 5 wall seconds, each giving the virtual time). At each progress line it reads, at once:
  - /proc/stat: the host's user, system, softirq, irq and idle time, and its context switches;
  - every thread of sitlnet: CPU (schedstat) and voluntary / involuntary context switches;
  - every robot's cgroup (cgroup v2 cpu.stat: usage, user, system) and the context switches of
    every thread of every process in it, with the CPU of each thread by name (PX4 names its
    threads after its modules: logger, mavlink_if0, wq:rate_ctrl, ...).
The window runs from the first progress line to the last: booting and stopping are outside it.
Prints one CSV row (per virtual second over the window; the host's CPU in CPU seconds), then
the autopilots' CPU by thread name to OUT_DIR/threads.csv, then the coordinator's iteration
times from summary.json. A benchmark, not a test.
"""
import glob
import json
import os
import re
import subprocess
import sys
import time

TICK = os.sysconf("SC_CLK_TCK")
PROGRESS = re.compile(r"^t=\s*([0-9.]+)/")


def read(path):
    try:
        with open(path) as f:
            return f.read()
    except OSError:
        return ""


def thread_stats(pid):
    """{tid: (comm, cpu_s, voluntary, involuntary)} for every thread of pid."""
    out = {}
    for task in glob.glob(f"/proc/{pid}/task/*"):
        stat = read(task + "/stat")
        status = read(task + "/status")
        if not stat or not status:
            continue
        comm = stat[stat.index("(") + 1:stat.rindex(")")]
        # schedstat's first field: nanoseconds on a CPU, exact (stat's utime and stime are ticks).
        schedstat = read(task + "/schedstat").split()
        if not schedstat:
            continue
        cpu_s = int(schedstat[0]) / 1e9
        vol = int(re.search(r"^voluntary_ctxt_switches:\s+(\d+)", status, re.M).group(1))
        invol = int(re.search(r"^nonvoluntary_ctxt_switches:\s+(\d+)", status, re.M).group(1))
        out[int(os.path.basename(task))] = (comm, cpu_s, vol, invol)
    return out


def host_stat():
    fields = {}
    for line in read("/proc/stat").splitlines():
        parts = line.split()
        if parts and parts[0] == "cpu":
            names = ["user", "nice", "system", "idle", "iowait", "irq", "softirq", "steal"]
            fields.update({n: int(v) / TICK for n, v in zip(names, parts[1:9])})
        elif parts and parts[0] == "ctxt":
            fields["ctxt"] = int(parts[1])
    return fields


def cgroup_root(scenario_name):
    for line in read("/proc/self/mountinfo").splitlines():
        if " - cgroup2 " in line:
            return os.path.join(line.split()[4], "sitlnet", scenario_name)
    return None


def robots_stat(root):
    """{robot: {"usage", "user", "system": s, "threads": {tid: ...}}}"""
    out = {}
    for folder in glob.glob(os.path.join(root, "*")):
        if not os.path.isdir(folder):
            continue
        stat = dict(line.split() for line in read(folder + "/cpu.stat").splitlines() if line)
        threads = {}
        for pid in read(folder + "/cgroup.procs").split():
            for tid, value in thread_stats(pid).items():
                threads[tid] = value
        out[os.path.basename(folder)] = {
            "usage": int(stat.get("usage_usec", 0)) / 1e6,
            "user": int(stat.get("user_usec", 0)) / 1e6,
            "system": int(stat.get("system_usec", 0)) / 1e6,
            "threads": threads,
        }
    return out


def sample(sitlnet_pid, root):
    return {"wall": time.monotonic(), "host": host_stat(), "sitlnet": thread_stats(sitlnet_pid),
            "robots": robots_stat(root)}


def main():
    sitlnet, scenario, out_dir, virtual_s, kind, n, load = sys.argv[1:8]
    name = re.search(r'^name:\s*"([^"]+)"', read(scenario), re.M).group(1)
    root = cgroup_root(name)
    log_path = os.path.join(out_dir, "log")
    with open(log_path, "w") as log:
        run = subprocess.Popen([sitlnet, "run", scenario, "--out", os.path.join(out_dir, "run")],
                               stdout=log, stderr=subprocess.STDOUT)
    samples = []  # (virtual_s, sample)
    seen = 0
    with open(log_path) as log:
        while True:
            line = log.readline()
            if not line:
                if run.poll() is not None:
                    break
                time.sleep(0.02)
                continue
            match = PROGRESS.match(line)
            if match and float(match.group(1)) < float(virtual_s):
                samples.append((float(match.group(1)), sample(run.pid, root)))
            seen += 1
    if run.wait() != 0 or len(samples) < 2:
        print(f"{kind},{n},failed or too short ({len(samples)} progress lines),,,,,,,,,,,,,{load}")
        sys.stderr.write(read(log_path)[-2000:])
        return 1
    (v0, a), (v1, b) = samples[0], samples[-1]
    virtual = v1 - v0
    wall = b["wall"] - a["wall"]
    per = lambda x: x / virtual  # noqa: E731

    host = {k: b["host"][k] - a["host"][k] for k in b["host"]}
    # sitlnet's threads: tid order (the main thread, then threads in creation order).
    sitlnet_rows = []
    for tid in sorted(b["sitlnet"]):
        comm, cpu, vol, invol = b["sitlnet"][tid]
        c0, v0_, i0 = a["sitlnet"].get(tid, (comm, 0, 0, 0))[1:]
        sitlnet_rows.append((tid, comm, cpu - c0, vol - v0_, invol - i0))
    robot_cpu = robot_user = robot_sys = robot_vol = robot_invol = 0.0
    by_name = {}
    for robot, rb in b["robots"].items():
        ra = a["robots"].get(robot)
        if ra is None:
            continue
        robot_cpu += rb["usage"] - ra["usage"]
        robot_user += rb["user"] - ra["user"]
        robot_sys += rb["system"] - ra["system"]
        for tid, (comm, cpu, vol, invol) in rb["threads"].items():
            c0, v0_, i0 = ra["threads"].get(tid, (comm, 0, 0, 0))[1:]
            robot_vol += vol - v0_
            robot_invol += invol - i0
            key = re.sub(r"\d+$", "#", comm) if kind == "arducopter" else comm
            by_name[key] = by_name.get(key, 0) + cpu - c0
    s = json.load(open(os.path.join(out_dir, "run", "summary.json")))
    m = s["metrics"]
    sitlnet_cpu = sum(r[2] for r in sitlnet_rows)
    print(f"{kind},{n},{virtual:.1f},{wall / virtual:.3f},"
          f"{per(robot_cpu):.3f},{per(robot_user):.3f},{per(robot_sys):.3f},"
          f"{per(sitlnet_cpu):.3f},"
          f"{per(host['user'] + host['nice']):.3f},{per(host['system']):.3f},"
          f"{per(host['softirq'] + host['irq']):.3f},{per(host['idle'] + host['iowait']):.3f},"
          f"{per(robot_vol) / int(n):.0f},{per(robot_invol) / int(n):.0f},"
          f"{per(sum(r[3] for r in sitlnet_rows)):.0f},{per(host['ctxt']):.0f},{load}")
    with open(os.path.join(out_dir, "threads.txt"), "w") as f:
        f.write(f"{kind} x{n}: window {virtual:.1f} virtual s, {wall:.1f} wall s\n")
        f.write("sitlnet threads (tid, name, CPU s / virtual s, voluntary, involuntary switches / virtual s):\n")
        for tid, comm, cpu, vol, invol in sitlnet_rows:
            if cpu > 0 or vol > 0:
                f.write(f"  {tid} {comm} {per(cpu):.3f} {per(vol):.0f} {per(invol):.0f}\n")
        f.write("autopilot threads by name, CPU s per virtual s per autopilot (share of the autopilots' CPU):\n")
        total = sum(by_name.values()) or 1
        for key, cpu in sorted(by_name.items(), key=lambda kv: -kv[1]):
            if cpu > 0:
                f.write(f"  {key} {per(cpu) / int(n):.4f} ({100 * cpu / total:.1f} %)\n")
        f.write("coordinator, per iteration (ms): " + ", ".join(
            f"{k} mean {m[k]['mean']:.3f} p99 {m[k]['p99']:.3f}"
            for k in ("t_phy_ms", "t_net_ms", "t_overhead_ms")) + "\n")
        physics = [r.get("physics") or {} for r in s["robots"]]
        answers = sum((p.get("px4") or {}).get("actuator_controls", 0) + p.get("json_frames", 0)
                      for p in physics)
        f.write(f"iterations {m['iterations']}, autopilot answers {answers} over {s['simulated_s']} s, "
                f"STF mean {m['stf']['mean']:.3f}, loop {s['resources']['loop_s']:.2f} s\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
