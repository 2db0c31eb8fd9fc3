#!/usr/bin/env bash
# Issue 48, item 3: deploy/kubernetes/sweep-job.yaml played with podman on this machine. The
# Indexed Job's pods (rendered by deploy/kubernetes/render-for-podman --sweep), two at once, each
# run one point of a lockstep sweep (2 rates, 2 flockers) into one shared folder; then
# `sitlnet sweep --collect` tabulates them. Oracle: the same sweep run on this host. Each point's
# trajectories.csv, deliveries.csv and medium.pcap must be equal byte for byte, and --collect
# must find every point finished. Then `podman kube down` and this script's cleanup must leave no
# pod, network, namespace or device. The pods run this checkout's build in the packages image
# (localhost/sitlnet-packages:test, made by scripts/container-test --prepare).
# Usage: tests/integration/kube_sweep_test.sh SOURCE_DIR SITLNET_BINARY
set -euo pipefail
source_dir=$(cd "$1" && pwd)
sitlnet=$2
image=localhost/sitlnet-packages:test

source "$(dirname "$0")/kube_test_requirements.sh"
kube_test_require kube_sweep_test "$source_dir" "$image"

source "$source_dir/deploy/kubernetes/podman-fleet.sh"
work=$(mktemp -d /tmp/sitlnet-kube-sweep.XXXXXX)
suffix=-ks$$
network=sitlnet$suffix
subnet=10.$((120 + $$ % 60)).$(($$ / 60 % 250))
pods=(sitlnet-sweep-0$suffix sitlnet-sweep-1$suffix)
netns_before=$(ip netns list | sort)
links_before=$(ip -o link show | awk -F': ' '{print $2}' | sort)
played=()

cleanup() {
  local status=$? file pod
  for file in "${played[@]}"; do podman kube down "$file" >/dev/null 2>&1 || true; done
  for pod in "${pods[@]}"; do podman pod rm -f "$pod" >/dev/null 2>&1 || true; done
  podman network rm "$network" >/dev/null 2>&1 || true
  rm -rf "$work"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

show_logs() {
  local pod
  for pod in "${pods[@]}"; do
    echo "--- $pod" >&2
    podman logs "$pod-point" 2>&1 | tail -15 >&2
  done
}

# The scenario: two flockers, 3 s of lockstep; the grid: two rates, one seed.
mkdir -p "$work/scenario"
scenario=$work/scenario/sweep.textproto
{
  echo "name: \"ks$(($$ % 100000))\""
  echo 'robot { name: "a" position_m { x: 0 y: -2 z: 0.2 } image: "flocker" args: ["--target", "40,0", "--altitude-m", "5"] }'
  echo 'robot { name: "b" position_m { x: 0 y: 2 z: 0.2 } image: "flocker" args: ["--target", "40,0", "--altitude-m", "5"] }'
  echo 'timing { duration_ms: 3000 pacing: PACING_LOCKSTEP }'
} >"$scenario"
grid=(--seeds 1 --set radio.rate_mbps=6,54)

# The reference first, on this host (before any pod, as kube_fleet_test.sh says why).
"$sitlnet" sweep "$scenario" "${grid[@]}" --out "$work/local" 2>"$work/local.err" ||
  { echo "kube_sweep_test: FAILED: the sweep on this host" >&2; cat "$work/local.err" >&2; exit 1; }

kube_play_containers_conf "$work"
"$source_dir/deploy/kubernetes/render-for-podman" --sweep --out "$work/pods" --suffix="$suffix" \
  --image "$image" --checkout "$source_dir" --scenario "$scenario" --runs "$work/runs" \
  --sweep-args="${grid[*]}" --completions 2 >/dev/null
podman network create --subnet "$subnet.0/24" "$network" >/dev/null
started_s=$SECONDS
for index in 0 1; do  # Both at once, as the Job's parallelism lets them run.
  played+=("$work/pods/sweep-$index.yaml")
  podman kube play --network "$network" --configmap "$work/pods/env.yaml" \
    "$work/pods/sweep-$index.yaml" >/dev/null 2>>"$work/play.log" ||
    { echo "kube_sweep_test: FAILED: kube play" >&2; cat "$work/play.log" >&2; exit 1; }
done
status=0
for pod in "${pods[@]}"; do
  exit_code=$(timeout 120 podman wait "$pod-point") ||
    { echo "kube_sweep_test: FAILED: $pod did not end within 120 s" >&2; show_logs; exit 1; }
  if [[ $exit_code != 0 ]]; then
    echo "kube_sweep_test: FAILED: $pod exited $exit_code" >&2
    show_logs
    exit 1
  fi
done
echo "kube_sweep_test: the pods ran both points in $((SECONDS - started_s)) s"

"$sitlnet" sweep "$scenario" "${grid[@]}" --collect --out "$work/runs/sweep" 2>"$work/collect.err" ||
  { echo "kube_sweep_test: FAILED: --collect" >&2; cat "$work/collect.err" >&2; exit 1; }
points=0
for folder in "$work/local"/*/; do
  point=$(basename "$folder")
  points=$((points + 1))
  for file in trajectories.csv deliveries.csv medium.pcap; do
    if cmp -s "$folder/$file" "$work/runs/sweep/$point/$file"; then
      echo "kube_sweep_test: $point: $file equal ($(stat -c %s "$folder/$file") B)"
    else
      echo "kube_sweep_test: FAILED: $point: $file differs between the pods and this host" >&2
      status=1
    fi
  done
done
((points == 2)) || { echo "kube_sweep_test: FAILED: $points points on this host, not 2" >&2; status=1; }

# podman kube down, as a user would, then the network: nothing of the sweep may be left.
for file in "${played[@]}"; do podman kube down "$file" >/dev/null; done
played=()
for pod in "${pods[@]}"; do
  if podman pod exists "$pod"; then
    echo "kube_sweep_test: FAILED: pod $pod left after kube down" >&2
    status=1
  fi
done
podman network rm "$network" >/dev/null
if [[ $(ip netns list | sort) != "$netns_before" ]]; then
  echo "kube_sweep_test: FAILED: network namespaces changed on the host" >&2
  status=1
fi
if [[ $(ip -o link show | awk -F': ' '{print $2}' | sort) != "$links_before" ]]; then
  echo "kube_sweep_test: FAILED: links on the host changed" >&2
  status=1
fi
exit $status
