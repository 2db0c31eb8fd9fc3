#!/usr/bin/env bash
# What hashing a run's outputs for summary.json's "outputs" costs (docs/performance.md, "Hashing
# the outputs"): a 22 s realtime run in which iperf3 sends 24 Mb/s of UDP over 802.11a at 54 Mb/s
# (a medium.pcap of about 67 MB), run RUNS times; prints each run's pcap size and
# resources.hash_outputs_s, then their median, and coreutils' sha256sum on the same pcap.
# Usage (root): bench/verify/hash_outputs.sh [RUNS] [SITLNET_BINARY]
set -euo pipefail
runs=${1:-3}
sitlnet=${2:-$(cd "$(dirname "$0")/../.." && pwd)/build/bin/sitlnet}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
third=$(( $$ % 250 ))
cat > "$work/hash.textproto" <<X
name: "hashb"
robot { name: "b" position_m { x: 5 y: 0 z: 0.2 } image: "iperf" args: ["-s", "-1"] }
robot { name: "c" position_m { x: 0 y: 5 z: 0.2 } image: "shell"
        args: "sleep 1; iperf3 -c 10.252.$third.1 -u -b 24M -l 1400 -t 20" }
addresses { wlan_subnet: "10.252.$third.0/24" ctl_subnet: "10.232.$third.0/24" }
radio { rate_mbps: 54 }
timing { duration_ms: 22000 pacing: PACING_REALTIME }
X
seconds=()
for run in $(seq "$runs"); do
  "$sitlnet" run "$work/hash.textproto" --out "$work/run$run" --no-progress > "$work/log$run" 2>&1
  read -r bytes hash_s < <(python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))
print(s['outputs']['medium.pcap']['bytes'], s['resources']['hash_outputs_s'])" "$work/run$run/summary.json")
  echo "run $run: medium.pcap $bytes B, every output hashed in $hash_s s"
  seconds+=("$hash_s")
done
printf '%s\n' "${seconds[@]}" | sort -g | awk '{ v[NR] = $1 } END { printf "median %.4f s over %d runs\n", v[int((NR + 1) / 2)], NR }'
start=$(date +%s.%N)
sha256sum "$work/run1/medium.pcap" > /dev/null
echo "sha256sum (coreutils) on run 1's medium.pcap: $(echo "$(date +%s.%N) - $start" | bc) s"
