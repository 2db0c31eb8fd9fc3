#!/bin/bash
# Real iperf3 (UDP) between two robots on 802.11ac, VHT MCS 9, 80 MHz, long guard interval,
# A-MPDU with best effort's limit at VHT's maximum (1048575 B: 64 MPDUs), 1 m apart, in dilated
# time: `sitlnet run` paces virtual time at FACTOR of the wall clock (realtime pacing) and the
# images' clocks run at the same FACTOR (libfaketime, docs/time.md), so iperf3 offers and counts
# in virtual seconds and sees the simulated rate, whatever the host's speed. Lockstep pacing has
# no fixed factor, so dilated images are refused there. The figure it is held to: ns-3 3.37's
# saturation throughput of the same cell with one sender (ns3_side_by_side saturation-ac, ns-3
# packet sockets), within 2 % (issue 44, item 7).
#
# iperf3 -u -l 1472 makes IPv4 packets of 1500 B, the cell's payload; iperf3 counts UDP payload,
# so its goodput is compared with ns-3's throughput times 1472 / 1500. Each round flies one run
# (seeds 1..ROUNDS) and reads the receiver's figure from the client's JSON; prints each round,
# the median and its ratio to ns-3's. Needs root; installs Debian's libns3-dev if missing.
# Usage: bench/ns3_reference/ac_iperf3_dilated.sh [build-dir] [rounds=3] [factor=0.25] [seconds=5]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
rounds=${2:-3}
factor=${3:-0.25}
seconds=${4:-5}
scenario=acdil
if [ "$(id -u)" != 0 ]; then
  echo "ac_iperf3_dilated.sh: needs root (namespaces, TAPs, sandboxes)" >&2
  exit 3
fi
dpkg -s libns3-dev > /dev/null 2>&1 || apt-get install -y --no-install-recommends libns3-dev > /dev/null
if [ -f "$build/CMakeCache.txt" ]; then
  cmake -S "$repo" -B "$build" > /dev/null
else
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
fi
cmake --build "$build" -j2 --target ns3_side_by_side sitlnet > /dev/null
if [ -e "/run/sitlnet/$scenario" ]; then
  echo "ac_iperf3_dilated.sh: scenario $scenario is already up (sitlnet down $scenario)" >&2
  exit 1
fi
work=$(mktemp -d)
trap '"$build/bin/sitlnet" down "$scenario" > /dev/null 2>&1 || true; rm -rf "$work"' EXIT

echo "# host: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); sitlnet at" \
  "$(git -C "$repo" rev-parse --short HEAD 2> /dev/null || echo unknown)"
ns3_line=$("$build/bin/ns3_side_by_side" saturation-ac "$rounds" "$seconds" | grep '^ns-3 ')
echo "# $ns3_line"
ns3_mbps=$(awk '{ print $2 }' <<< "$ns3_line")

# The run: the server starts at once, the client after a virtual second; -O 1 leaves out
# iperf3's first second (the Block Ack agreement and the queue filling).
duration_ms=$(( (seconds + 4) * 1000 ))
cat > "$work/$scenario.textproto" << EOF
name: "$scenario"
robot { name: "a" position_m { x: 0 y: 0 z: 1 } image: "shell"
        args: "sleep 1; iperf3 -c 10.77.0.2 -u -b 600M -l 1472 -t $((seconds + 1)) -O 1 --json" }
robot { name: "b" position_m { x: 1 y: 0 z: 1 } image: "iperf" args: ["-s", "-1"] }
radio { standard: STANDARD_80211AC mcs: 9 channel_width_mhz: 80 aggregation: true
        ampdu_max_bytes_be: 1048575 }
timing { duration_ms: $duration_ms pacing: PACING_REALTIME realtime_factor: $factor }
EOF
echo "round,goodput_mbps,lost_percent,lag_p99_ms,load1"
for round in $(seq 1 "$rounds"); do
  out=$work/run-$round
  load1=$(cut -d' ' -f1 /proc/loadavg)
  "$build/bin/sitlnet" run "$work/$scenario.textproto" --out "$out" --seed "$round" \
    --no-progress > "$work/run.log" 2>&1 || { cat "$work/run.log" >&2; exit 1; }
  python3 - "$out" "$round" "$load1" << 'PY'
import json, sys
out, round_, load1 = sys.argv[1:]
log = open(out + "/robots/a.log").read()
end = json.loads(log[log.index("{"):log.rindex("}") + 1])["end"]
# The server's own figure, reported back to the client (its "receiver" line); end.sum mixes the
# sender's packet count, which leaves out the omitted second, with the server's losses.
received = end["sum_received"]
summary = json.load(open(out + "/summary.json"))
print("%s,%.3f,%.2f,%s,%s" % (round_, received["bits_per_second"] / 1e6,
                              received["lost_percent"], summary["metrics"]["lag_ms"]["p99"], load1))
PY
  rm -rf "$out"
done | tee "$work/rows.csv"
python3 - "$work/rows.csv" "$ns3_mbps" << 'PY'
import statistics, sys
lines = [l.split(",") for l in open(sys.argv[1]) if l[0].isdigit()]
goodput = [float(l[1]) for l in lines]
ns3 = float(sys.argv[2]) * 1472 / 1500
median = statistics.median(goodput)
print("iperf3 goodput median %.3f Mb/s (%.3f-%.3f); ns-3 saturation as UDP payload %.3f Mb/s;"
      " ratio %.4f (%+.2f %%)" % (median, min(goodput), max(goodput), ns3, median / ns3,
                                  (median / ns3 - 1) * 100))
PY
