#!/usr/bin/env python3
"""sitlnet's own cost per autopilot step (issue 46, item 3; docs/performance.md, "The harness's
share per autopilot step").

  harness_per_step.py SITLNET KIND N VIRTUAL_S OUT_DIR

Flies N autopilots of KIND in lockstep for VIRTUAL_S virtual seconds and counts, on sitlnet's
physics threads only ("sitlnet-physics", the iteration's thread, and "sitlnet-step", the step
pool's worker): system calls (perf's raw_syscalls:sys_enter), context switches and CPU time
(task-clock). Each is divided by the autopilot steps answered (summary.json: PX4's actuator
controls, ArduPilot JSON frames). KIND:
  test-px4, test-json  the test_autopilot stand-in (PX4 simulator MAVLink, ArduPilot JSON):
                       the floor, an autopilot that costs almost nothing;
  px4, arducopter      the real autopilots (SITLNET_PX4_DIR, SITLNET_ARDUPILOT_DIR).
perf is attached once the physics thread exists (before the robots start) and stopped when the run
ends: the count covers the whole loop. Prints one CSV row:
  kind,robots,stf,answers,syscalls_per_step,switches_per_step,cpu_us_per_step,
  physics_syscalls_per_step,step_switches_per_step,loop_s
A benchmark, not a test.
"""
import json
import os
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
THREADS = ("sitlnet-physics", "sitlnet-step")


def scenario(kind, n, path, seconds):
    if kind in ("px4", "arducopter"):
        subprocess.check_call([sys.executable, os.path.join(HERE, "fleet_scenario.py"), kind,
                               str(n), path, str(seconds), "LOCKSTEP"])
        return
    side = int(n ** 0.5 + 0.999)
    with open(path, "w") as f:
        f.write('name: "hpsbench"\naddresses { wlan_subnet: "10.70.0.0/16" ctl_subnet: "10.71.0.0/16" }\n')
        for i in range(n):
            x, y = 10 * (i % side), 10 * (i // side)
            if kind == "test-json":
                link, args = "ardupilot_json_port: 9002", '"--json-port", "9002"'
            else:
                link, args = "px4_sim_port: 4560", '"--px4-port", "4560"'
            f.write(f'robot {{ name: "r{i}" position_m {{ x: {x} y: {y} z: 0.2 }} {link} '
                    f'image: "test_autopilot" args: [{args}, "--waypoint", "{x + 20},{y}"] }}\n')
        f.write(f"timing {{ duration_ms: {seconds * 1000} pacing: PACING_LOCKSTEP }}\n")


def named_threads(pid):
    found = {}
    try:
        for tid in os.listdir(f"/proc/{pid}/task"):
            try:
                with open(f"/proc/{pid}/task/{tid}/comm") as f:
                    name = f.read().strip()
            except OSError:
                continue
            if name in THREADS:
                found[name] = int(tid)
    except OSError:
        pass
    return found


def main():
    sitlnet, kind, n, seconds, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "s.textproto")
    scenario(kind, n, path, seconds)
    log = open(os.path.join(out, "log"), "w")
    run = subprocess.Popen([sitlnet, "run", path, "--out", os.path.join(out, "run"), "--no-progress"],
                           stdout=log, stderr=subprocess.STDOUT)
    # The step pool's worker is made with the world, before the physics thread; with
    # SITLNET_PHYSICS_THREADS=1 there is none.
    threads = {}
    while run.poll() is None and "sitlnet-physics" not in threads:
        threads = named_threads(run.pid)
        time.sleep(0.005)
    if "sitlnet-physics" not in threads:
        run.wait()
        print(f"{kind},{n},failed: threads {sorted(threads)} not found", file=sys.stderr)
        return 1
    perf_out = os.path.join(out, "perf.csv")
    perf = subprocess.Popen(["perf", "stat", "-x,", "--per-thread", "-o", perf_out,
                             "-e", "raw_syscalls:sys_enter,context-switches,task-clock",
                             "-t", ",".join(str(t) for t in threads.values())],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    code = run.wait()
    perf.send_signal(signal.SIGINT)
    perf.wait()
    if code != 0:
        print(f"{kind},{n},failed (exit {code})", file=sys.stderr)
        with open(os.path.join(out, "log")) as f:
            sys.stderr.write("".join(line for line in f if line.startswith("sitlnet run:"))[-600:])
        return 1
    by_tid = {tid: name for name, tid in threads.items()}
    counts = {name: {} for name in THREADS}
    for line in open(perf_out):
        parts = line.strip().split(",")
        if len(parts) < 4 or not parts[1].replace(".", "").isdigit():
            continue
        tid = int(parts[0].rsplit("-", 1)[-1])
        if tid in by_tid:
            counts[by_tid[tid]][parts[3]] = float(parts[1])
    s = json.load(open(os.path.join(out, "run", "summary.json")))
    answers = 0
    for r in s["robots"]:
        p = r.get("physics") or {}
        answers += (p.get("px4") or {}).get("actuator_controls", 0) + p.get("json_frames", 0)
    if answers == 0:
        print(f"{kind},{n},failed: no autopilot answered", file=sys.stderr)
        return 1
    total = lambda event: sum(c.get(event, 0) for c in counts.values())  # noqa: E731
    physics, step = counts["sitlnet-physics"], counts["sitlnet-step"]
    print(f"{kind},{n},{s['metrics']['stf']['mean']:.4f},{answers},"
          f"{total('raw_syscalls:sys_enter') / answers:.2f},{total('context-switches') / answers:.3f},"
          f"{total('task-clock') * 1e3 / answers:.2f},"  # perf: ms
          f"{physics.get('raw_syscalls:sys_enter', 0) / answers:.2f},"
          f"{step.get('context-switches', 0) / answers:.3f},{s['resources']['loop_s']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
