#!/usr/bin/env bash
# Benchmark (issue 35, item 5): N flocking robots (bench/scale's scaled case study) on 1, 2 and 4
# node pods of deploy/kubernetes, played with podman on this machine (deploy/kubernetes/
# podman-fleet.sh), against the same scenario on one host (`sitlnet run --one-host`).
# Per run: the coordinator's STF and T_phy (which holds the round trip to the nodes), and the
# bytes each node pod's eth0 sent and received, per iteration. Rounds alternate the variants'
# order (ABBA). Every pod shares this machine's cores: this measures the link, not a speed-up.
# Writes OUT/runs.csv and prints it. Needs root, podman and localhost/sitlnet-packages:test.
#
#   sudo bench/fleet/fleet_pods.sh [N=64] [SECONDS=10] [ROUNDS=2] [NODES="1 2 4"] [OUT]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source_dir=$(cd "$here/../.." && pwd)
n=${1:-64} seconds=${2:-10} rounds=${3:-2} node_counts=${4:-"1 2 4"}
out=${5:-/tmp/sitlnet-fleet-pods-$(date -u +%Y%m%d-%H%M%S)}
image=localhost/sitlnet-packages:test
sitlnet=$source_dir/build/bin/sitlnet
source "$source_dir/deploy/kubernetes/podman-fleet.sh"
mkdir -p "$out"
trap '[[ -n ${FLEET_NETWORK:-} ]] && fleet_pods_end' EXIT

# The scenario for NODES node pods: bench/scale's fleet, lockstep, SECONDS long, robots in blocks.
write_scenario() {  # NODES FILE
  python3 "$source_dir/bench/scale/gen_scenario.py" "$n" "$2.tmp"
  python3 - "$1" "$2.tmp" "$2" "$seconds" <<'PY'
import re, sys
nodes, source, target, seconds = int(sys.argv[1]), sys.argv[2], sys.argv[3], float(sys.argv[4])
text = open(source).read()
text = re.sub(r"timing \{[^}]*\}", "timing { duration_ms: %d pacing: PACING_LOCKSTEP seed: 1 }"
              % int(seconds * 1000), text)
text += "".join('nodes { name: "sitlnet-node-%d" }\n' % i for i in range(nodes))
text += "node_assignment: NODE_ASSIGNMENT_BLOCKS\n"
open(target, "w").write(text)
PY
  rm -f "$2.tmp"
}

# Mean of a metrics line's first number ("  STF  mean 0.0579 ...") in a summary printed on stderr.
mean_of() { awk -v key="$1" '$1 == key {print $3; exit}' "$2"; }

echo "variant,round,nodes,robots,simulated_s,wall_s,stf_mean,t_phy_ms,t_total_ms,iterations,node_tx_bytes_per_iteration,node_rx_bytes_per_iteration" >"$out/runs.csv"
for round in $(seq 1 "$rounds"); do
  variants="one-host $node_counts"
  ((round % 2 == 0)) && variants=$(echo "$variants" | tr ' ' '\n' | tac | tr '\n' ' ')
  for variant in $variants; do
    dir=$out/$variant-$round
    mkdir -p "$dir/scenario"
    nodes=$([[ $variant == one-host ]] && echo 1 || echo "$variant")
    write_scenario "$nodes" "$dir/scenario/fleet.textproto"
    iterations=$((${seconds%.*} * 100))
    started=$(date +%s%N)
    tx=0 rx=0
    if [[ $variant == one-host ]]; then
      "$sitlnet" run "$dir/scenario/fleet.textproto" --one-host --out "$dir/run" --no-progress \
        2>"$dir/log"
      log=$dir/log
    else
      fleet_pods_begin "$dir" "$source_dir" "$image" "$dir/scenario/fleet.textproto" "$nodes"
      fleet_pods_play
      exit_code=$(timeout 900 podman wait "$FLEET_COORDINATOR")
      podman logs "$FLEET_COORDINATOR" >"$dir/log" 2>&1
      log=$dir/log
      [[ $exit_code == 0 ]] || { fleet_pods_show_logs; exit 1; }
      # Lingering nodes: their eth0 counters hold the whole run's link (and the handshake).
      for container in "${FLEET_NODE_CONTAINERS[@]}"; do
        tx=$((tx + $(podman exec "$container" cat /sys/class/net/eth0/statistics/tx_bytes)))
        rx=$((rx + $(podman exec "$container" cat /sys/class/net/eth0/statistics/rx_bytes)))
      done
      fleet_pods_end
      unset FLEET_NETWORK
    fi
    wall_s=$(awk -v a="$started" -v b="$(date +%s%N)" 'BEGIN {printf "%.1f", (b - a) / 1e9}')
    printf "%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n" "$variant" "$round" \
      "$([[ $variant == one-host ]] && echo 0 || echo "$nodes")" "$n" "$seconds" "$wall_s" \
      "$(mean_of STF "$log")" "$(mean_of T_phy "$log")" "$(mean_of T_total "$log")" \
      "$iterations" "$((tx / nodes / iterations))" "$((rx / nodes / iterations))" \
      >>"$out/runs.csv"
    tail -1 "$out/runs.csv"
  done
done
cat "$out/runs.csv"
