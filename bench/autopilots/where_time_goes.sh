#!/bin/bash
# Where the time of an idle lockstep fleet of real autopilots goes (issue 46, item 1;
# docs/performance.md, "Where the time goes"). For each size and kind, one run of SECONDS
# virtual seconds through where_time_goes.py, which reads /proc and the robots' cgroups at each
# progress line (every 5 wall s) and prints, per virtual second of the window between the first
# and the last line:
#   wall_s        wall seconds (the window's STF);
#   ap_cpu_s      the autopilots' cgroups, all of them (user, system);
#   sitlnet_cpu_s sitlnet's threads (OUT/<kind>-<n>/threads.txt has them one by one);
#   host_*        the host's CPU seconds from /proc/stat: user, system, softirq + irq, idle;
#   ap_wakeups    voluntary context switches of one autopilot (all its threads): its wake-ups;
#   ap_preempted  its involuntary ones; sitlnet_wakeups sitlnet's voluntary switches;
#   host_ctxt     the host's context switches (every process of the host).
# threads.txt also has the autopilots' CPU by thread name and the coordinator's T_phy, T_net and
# T_overhead per iteration. Other processes of the host show in host_*: note the load average.
#
#   bench/autopilots/where_time_goes.sh [BUILD=build] [SECONDS=20] [SIZES="1 8 16"] [OUT=dir] [ARGS]
#       (KINDS="px4 arducopter" by default; ARGS: extra robot args, e.g. --lean)
set -euo pipefail
build=${1:-build} seconds=${2:-20} sizes=${3:-"1 8 16"} out=${4:-$(mktemp -d /tmp/sitlnet-where-XXXXXX)}
shift $(( $# < 4 ? $# : 4 ))
: "${SITLNET_PX4_DIR:?point it at a PX4 build (docs/autopilots.md)}"
: "${SITLNET_ARDUPILOT_DIR:?point it at an ArduCopter SITL build (docs/autopilots.md)}"
here=$(dirname "$0")
echo "kind,robots,window_virtual_s,wall_s,ap_cpu_s,ap_user_s,ap_system_s,sitlnet_cpu_s,host_user_s,host_system_s,host_softirq_s,host_idle_s,ap_wakeups,ap_preempted,sitlnet_wakeups,host_ctxt,load1"
for n in $sizes; do
  for kind in ${KINDS:-px4 arducopter}; do
    dir="$out/$kind-$n"
    rm -rf "$dir" && mkdir -p "$dir"
    # At least 200 / n virtual seconds: a small fleet runs fast, and the window needs two lines.
    secs=$(( seconds > 200 / n ? seconds : 200 / n ))
    python3 "$here/fleet_scenario.py" "$kind" "$n" "$dir/s.textproto" "$secs" LOCKSTEP "$@"
    python3 "$here/where_time_goes.py" "$build/bin/sitlnet" "$dir/s.textproto" "$dir" "$secs" \
      "$kind" "$n" "$(cut -d' ' -f1 /proc/loadavg)" || true
    rm -rf "$dir/run"
  done
done
echo "details: $out/*/threads.txt" >&2
