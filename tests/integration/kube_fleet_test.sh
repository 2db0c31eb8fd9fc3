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

missing() {
  if [[ "${CI:-}" == true ]]; then
    echo "kube_fleet_test: FAILED: $* (CI=true: required)" >&2
    exit 1
  fi
  echo "kube_fleet_test: skipped: $*" >&2
  exit 77
}
[[ $(id -u) -eq 0 ]] || missing "needs root (podman kube play of pods with NET_ADMIN)"
command -v podman >/dev/null || missing "podman is not installed (scripts/setup installs it)"
if [[ "${SITLNET_MIN_CAPS:-}" == 1 ]]; then  # the container pass (scripts/container-test)
  echo "kube_fleet_test: skipped: podman needs more than CAP_NET_ADMIN + CAP_SYS_ADMIN" >&2
  exit 77
fi
podman image exists "$image" ||
  missing "no image $image (sudo scripts/container-test --prepare makes it)"
[[ -x "$source_dir/build/bin/sitlnet" ]] || missing "no build in $source_dir/build (the pods run it)"

# Names of this run only: every cleanup below is by these exact names.
suffix=-kt$$
network=sitlnet$suffix
subnet_prefix=10.$((180 + $$ % 60)).$(($$ / 60 % 250))
work=$(mktemp -d /tmp/sitlnet-kube-test.XXXXXX)
netns_before=$(ip netns list | sort)
links_before=$(ip -o link show | awk -F': ' '{print $2}' | sort)
played=()

cleanup() {
  local status=$?
  for file in "${played[@]}"; do podman kube down "$file" >/dev/null 2>&1 || true; done
  for pod in sitlnet-coordinator$suffix sitlnet-node-0$suffix sitlnet-node-1$suffix; do
    podman pod rm -f "$pod" >/dev/null 2>&1 || true
  done
  podman network rm "$network" >/dev/null 2>&1 || true
  rm -rf "$work"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The scenario: four flockers, interleaved over the StatefulSet's two pods (their hostnames).
mkdir -p "$work/scenario" "$work/runs"
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
head -c 32 /dev/urandom >"$work/key"
chmod 600 "$work/key"

# podman 4.3's kube play takes no runtime or ulimit flags: a containers.conf of this run's own.
# runc: crun refuses hybrid cgroup hosts. Limits at or below the host's hard ones (podman's
# defaults are above this host's, and a container may not raise them).
hard_files=$(ulimit -Hn)
[[ $hard_files == unlimited ]] && hard_files=1048576
cat >"$work/containers.conf" <<EOF
[containers]
default_ulimits = ["nofile=$hard_files:$hard_files", "nproc=4096:4096"]
[engine]
runtime = "runc"
EOF
export CONTAINERS_CONF=$work/containers.conf

"$source_dir/deploy/kubernetes/render-for-podman" --out "$work/pods" --suffix="$suffix" \
  --image "$image" --checkout "$source_dir" --key "$work/key" --scenario "$scenario" \
  --runs "$work/runs" --coordinator-ip "$subnet_prefix.10" >/dev/null
podman network create --subnet "$subnet_prefix.0/24" "$network" >/dev/null

started_s=$SECONDS
play() {  # FILE IP
  played+=("$1")
  # Its warnings (e.g. "No more static macs left") go to a file, shown if the run fails.
  podman kube play --network "$network" --ip "$2" --configmap "$work/pods/env.yaml" "$1" \
    >/dev/null 2>>"$work/play.log" || { cat "$work/play.log" >&2; exit 1; }
}
play "$work/pods/coordinator.yaml" "$subnet_prefix.10"
play "$work/pods/node-0.yaml" "$subnet_prefix.11"
play "$work/pods/node-1.yaml" "$subnet_prefix.12"
coordinator=sitlnet-coordinator$suffix-coordinator
show_logs() {
  for container in $coordinator sitlnet-node-0$suffix-node sitlnet-node-1$suffix-node; do
    echo "--- $container" >&2
    podman logs "$container" 2>&1 | tail -15 >&2
  done
}
status=0
if [[ $mode == kill ]]; then
  # Mid-run: robot b (on node 1) has flown a simulated second. Polled: the file is on a hostPath,
  # the pod's claim, in which the node writes its folder /runs/$(hostname).
  b_log=$work/runs/sitlnet-node-1/sitlnet-node-1/robots/b.log
  for ((tries = 0; tries < 600; tries++)); do
    grep -q 't=1.00' "$b_log" 2>/dev/null && break
    sleep 0.1
  done
  grep -q 't=1.00' "$b_log" 2>/dev/null ||
    { echo "kube_fleet_test: FAILED: robot b never reached 1 s" >&2; show_logs; exit 1; }
  killed_s=$SECONDS
  podman kill sitlnet-node-1$suffix-node >/dev/null
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
  survivor_log=$(podman logs sitlnet-node-0$suffix-node 2>&1)
  if [[ $survivor_log != *'sitlnet-node-0: stopped: '* ]] ||
    [[ -n $(podman exec sitlnet-node-0$suffix-node ip netns list) ]]; then
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
  # The reference: the same scenario, every robot on this host.
  "$sitlnet" run "$scenario" --one-host --out "$work/one-host" --no-progress \
    2>"$work/one-host.err" ||
    { echo "kube_fleet_test: FAILED: the one-host run" >&2; cat "$work/one-host.err" >&2; exit 1; }
  for file in trajectories.csv medium.pcap deliveries.csv; do
    if cmp "$work/one-host/$file" "$work/runs/sitlnet-coordinator/run/$file"; then
      echo "kube_fleet_test: $file equal ($(stat -c %s "$work/one-host/$file") B)"
    else
      echo "kube_fleet_test: FAILED: $file differs between the pods and one host" >&2
      status=1
    fi
  done
fi

# podman kube down, as a user would, and the network removed: nothing of the run may be left.
for file in "${played[@]}"; do podman kube down "$file" >/dev/null; done
played=()
for pod in sitlnet-coordinator$suffix sitlnet-node-0$suffix sitlnet-node-1$suffix; do
  if podman pod exists "$pod"; then
    echo "kube_fleet_test: FAILED: pod $pod left after kube down" >&2
    status=1
  fi
done
if [[ $(ip netns list | sort) != "$netns_before" ]]; then
  echo "kube_fleet_test: FAILED: network namespaces changed on the host" >&2
  status=1
fi
podman network rm "$network" >/dev/null
if [[ $(ip -o link show | awk -F': ' '{print $2}' | sort) != "$links_before" ]]; then
  echo "kube_fleet_test: FAILED: links on the host changed:" \
    "$(diff <(echo "$links_before") <(ip -o link show | awk -F': ' '{print $2}' | sort) | grep '^[<>]')" >&2
  status=1
fi
exit $status
