#!/bin/bash
# Places each robot of a running scenario in a v1 cpu cgroup of its own with equal weight
# (cpu.shares 1024), for rate_spread.sh's WEIGHTS=equal (issue 46, item 6; docs/performance.md,
# "Realtime: the spread of the autopilots' rates"). An experiment, not what sitlnet does: on a
# host with realtime group scheduling (cpu.rt_runtime_us in the cpu hierarchy) a process in such
# a group may use SCHED_FIFO (PX4 asks for it) only within the group's realtime budget, so each
# robot gets RT_BUDGET_US / N of every second. The scenario's folder weighs N robots, as its
# robots' processes did as single tasks beside the host's others.
#
#   equal_cpu_weights.sh SCENARIO N [RT_BUDGET_US=900000]   (runs until the scenario's cgroups go)
set -euo pipefail
scenario=$1 n=$2 budget=${3:-900000}
v2=$(awk '$3 == "cgroup2" { print $2; exit }' /proc/mounts)
cpu=$(awk '$3 == "cgroup" && $4 ~ /(^|,)cpu(,|$)/ { print $2; exit }' /proc/mounts)
# Only a host with cgroup v1's cpu hierarchy (cpu.shares, cpu.rt_runtime_us) can run it.
[ -n "$cpu" ] && [ -d "$cpu" ] || { echo "$0: no cgroup v1 cpu hierarchy on this host" >&2; exit 2; }
top="$cpu/sitlnet-weights-$scenario"
mkdir -p "$top"
echo $((1024 * n)) > "$top/cpu.shares"
[ -f "$top/cpu.rt_runtime_us" ] && echo "$budget" > "$top/cpu.rt_runtime_us"
# On exit each group's tasks go back to the hierarchy's root, so that the groups can be removed.
trap 'for d in "$top"/*/; do [ -d "$d" ] && { for p in $(cat "$d/cgroup.procs" 2>/dev/null); do echo "$p" > "$cpu/cgroup.procs" 2>/dev/null || true; done; rmdir "$d" 2>/dev/null || true; }; done; rmdir "$top" 2>/dev/null || true' EXIT
seen=0
for _ in $(seq 1 600); do
  robots=$(ls -d "$v2/sitlnet/$scenario"/*/ 2>/dev/null || true)
  [ -z "$robots" ] && { (( seen )) && break; sleep 0.2; continue; }
  seen=1
  for r in $robots; do
    name=$(basename "$r")
    dir="$top/$name"
    if [ ! -d "$dir" ]; then
      mkdir "$dir"
      echo 1024 > "$dir/cpu.shares"
      [ -f "$dir/cpu.rt_runtime_us" ] && echo $((budget / n)) > "$dir/cpu.rt_runtime_us"
    fi
    for pid in $(cat "$r/cgroup.procs" 2>/dev/null); do
      grep -qx "$pid" "$dir/cgroup.procs" 2>/dev/null || echo "$pid" > "$dir/cgroup.procs" 2>/dev/null || true
    done
  done
  sleep 0.5
done
