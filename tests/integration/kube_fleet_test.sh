#!/usr/bin/env bash
# Issue 35, item 3: deploy/kubernetes/ played with podman on this machine. The coordinator pod and
# two node pods (the StatefulSet, rendered into pods by deploy/kubernetes/render-for-podman) run a
# lockstep fleet of 4 flockers over real TCP between pod networks; the run must equal the one-host
# run of the same scenario byte for byte (trajectories.csv, medium.pcap, deliveries.csv). Then
# `podman kube down` and this script's cleanup must leave no pod, network, namespace or device.
# The pods run this checkout's build in the packages image (localhost/sitlnet-packages:test,
# made by scripts/container-test --prepare), as scripts/container-test does.
# MODE kill (issue 35, item 4): node pod 1 is killed mid-run; the coordinator must exit 1 within
# 30 s naming it and its robots, and the surviving node must have taken its robots down.
# Without root, podman or that image: a skip (exit 77) that says why; under CI=true a failure.
# Usage: tests/integration/kube_fleet_test.sh SOURCE_DIR SITLNET_BINARY [identity|kill]
set -euo pipefail
source_dir=$(cd "$1" && pwd)
sitlnet=$2
mode=${3:-identity}
image=localhost/sitlnet-packages:test

source "$(dirname "$0")/kube_test_requirements.sh"
kube_test_require kube_fleet_test "$source_dir" "$image"

source "$source_dir/deploy/kubernetes/podman-fleet.sh"
work=$(mktemp -d /tmp/sitlnet-kube-test.XXXXXX)
netns_before=$(ip netns list | sort)
links_before=$(ip -o link show | awk -F': ' '{print $2}' | sort)
FLEET_PLAYED=()

cleanup() {
  local status=$?
  [[ -n ${FLEET_NETWORK:-} ]] && fleet_pods_end
  rm -rf "$work"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The scenario: four flockers, interleaved over the StatefulSet's two pods (their hostnames).
mkdir -p "$work/scenario"
scenario=$work/scenario/fleet.textproto
name=kt$(($$ % 100000))
{
  echo "name: \"$name\""
  node=0
  for robot in "a x: 0 y: -2" "b x: 0 y: 2" "c x: -4 y: -2" "d x: -4 y: 2"; do
    read -r robot_name position <<<"$robot"
    echo "robot { name: \"$robot_name\" node: \"sitlnet-node-$node\" position_m { $position z: 0.2 }" \
      "image: \"flocker\" args: [\"--target\", \"40,0\", \"--altitude-m\", \"5\"] lidar { rays: 8 } }"
    node=$((1 - node))
  done
  echo 'nodes { name: "sitlnet-node-0" } nodes { name: "sitlnet-node-1" }'
  # kill: ten minutes, so that the run is still going when a node is killed.
  echo "timing { duration_ms: $([[ $mode == kill ]] && echo 600000 || echo 3000)" \
    "pacing: PACING_LOCKSTEP seed: 5 }"
} >"$scenario"

# The reference first: the same scenario, every robot on this host. Before any pod: a pod that
# stops tears its network namespace out of /run/netns, and a robot's sandbox starting then
# fails to remount it (bubblewrap: "Unable to apply mount flags ... Invalid argument").
if [[ $mode == identity ]]; then
  "$sitlnet" run "$scenario" --one-host --out "$work/one-host" --no-progress \
    2>"$work/one-host.err" ||
    { echo "kube_fleet_test: FAILED: the one-host run" >&2; cat "$work/one-host.err" >&2; exit 1; }
fi

fleet_pods_begin "$work" "$source_dir" "$image" "$scenario" 2
started_s=$SECONDS
fleet_pods_play
coordinator=$FLEET_COORDINATOR
show_logs() { fleet_pods_show_logs; }
status=0
if [[ $mode == kill ]]; then
  # Mid-run: robot b (on node 1) has flown a simulated second. Polled: the file is on a hostPath.
  b_log=${FLEET_NODE_DIRS[1]}/robots/b.log
  for ((tries = 0; tries < 600; tries++)); do
    grep -q 't=1.00' "$b_log" 2>/dev/null && break
    sleep 0.1
  done
  grep -q 't=1.00' "$b_log" 2>/dev/null ||
    { echo "kube_fleet_test: FAILED: robot b never reached 1 s" >&2; show_logs; exit 1; }
  killed_s=$SECONDS
  podman kill "${FLEET_NODE_CONTAINERS[1]}" >/dev/null
  coordinator_exit=$(timeout 30 podman wait "$coordinator") ||
    { echo "kube_fleet_test: FAILED: the coordinator ran on 30 s after the kill" >&2; exit 1; }
  echo "kube_fleet_test: the coordinator exited $coordinator_exit $((SECONDS - killed_s)) s after the kill"
  expected="node 'sitlnet-node-1' (robots b, d) failed during iteration"
  # Logs read whole first: `grep -q` ending a pipe early would fail it (pipefail, SIGPIPE).
  coordinator_log=$(podman logs "$coordinator" 2>&1)
  if [[ $coordinator_exit != 1 || $coordinator_log != *"$expected"* ]]; then
    echo "kube_fleet_test: FAILED: expected exit 1 and \"$expected\"" >&2
    show_logs
    status=1
  fi
  # The survivor lingers (so that a StatefulSet does not restart it), its robots gone.
  survivor_log=$(podman logs "${FLEET_NODE_CONTAINERS[0]}" 2>&1)
  if [[ $survivor_log != *'sitlnet-node-0: stopped: '* ]] ||
    [[ -n $(podman exec "${FLEET_NODE_CONTAINERS[0]}" ip netns list) ]]; then
    echo "kube_fleet_test: FAILED: node 0 did not stop and take its robots down" >&2
    show_logs
    status=1
  fi
else
  coordinator_exit=$(timeout 180 podman wait "$coordinator") || {
    echo "kube_fleet_test: FAILED: the coordinator pod did not end within 180 s" >&2
    show_logs
    exit 1
  }
  pods_s=$((SECONDS - started_s))
  if [[ $coordinator_exit != 0 ]]; then
    echo "kube_fleet_test: FAILED: the coordinator pod exited $coordinator_exit" >&2
    show_logs
    exit 1
  fi
  echo "kube_fleet_test: pods ran the fleet in ${pods_s} s"
  for file in trajectories.csv medium.pcap deliveries.csv; do
    if cmp "$work/one-host/$file" "$FLEET_RUN_DIR/$file"; then
      echo "kube_fleet_test: $file equal ($(stat -c %s "$work/one-host/$file") B)"
    else
      echo "kube_fleet_test: FAILED: $file differs between the pods and one host" >&2
      status=1
    fi
  done
fi

# podman kube down, as a user would, then the network: nothing of the run may be left.
for file in "${FLEET_PLAYED[@]}"; do podman kube down "$file" >/dev/null; done
for pod in sitlnet-coordinator$FLEET_SUFFIX sitlnet-node-0$FLEET_SUFFIX sitlnet-node-1$FLEET_SUFFIX; do
  if podman pod exists "$pod"; then
    echo "kube_fleet_test: FAILED: pod $pod left after kube down" >&2
    status=1
  fi
done
fleet_pods_end
if [[ $(ip netns list | sort) != "$netns_before" ]]; then
  echo "kube_fleet_test: FAILED: network namespaces changed on the host" >&2
  status=1
fi
if [[ $(ip -o link show | awk -F': ' '{print $2}' | sort) != "$links_before" ]]; then
  echo "kube_fleet_test: FAILED: links on the host changed:" \
    "$(diff <(echo "$links_before") <(ip -o link show | awk -F': ' '{print $2}' | sort) | grep '^[<>]')" >&2
  status=1
fi
exit $status
