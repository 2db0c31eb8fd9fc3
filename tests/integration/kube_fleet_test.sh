#!/usr/bin/env bash
# Issue 35, item 3: deploy/kubernetes/ played with podman on this machine. The coordinator pod and
# two node pods (the StatefulSet, rendered into pods by deploy/kubernetes/render-for-podman) run a
# lockstep fleet of 4 flockers over real TCP between pod networks; the run must equal the one-host
# run of the same scenario byte for byte (trajectories.csv, medium.pcap, deliveries.csv). Then
# `podman kube down` and this script's cleanup must leave no pod, network, namespace or device.
# The pods run this checkout's build in the packages image (localhost/sitlnet-packages:test,
# made by scripts/container-test --prepare), as scripts/container-test does.
# Without root, podman or that image: a skip (exit 77) that says why; under CI=true a failure.
# Usage: tests/integration/kube_fleet_test.sh SOURCE_DIR SITLNET_BINARY
set -euo pipefail
source_dir=$(cd "$1" && pwd)
sitlnet=$2
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
if [[ -e /run/.containerenv || -e /.dockerenv ]]; then
  echo "kube_fleet_test: skipped: inside a container (pods there need more than its capabilities)" >&2
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
  echo 'timing { duration_ms: 3000 pacing: PACING_LOCKSTEP seed: 5 }'
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
  podman kube play --network "$network" --ip "$2" --configmap "$work/pods/env.yaml" "$1" \
    >/dev/null
}
play "$work/pods/coordinator.yaml" "$subnet_prefix.10"
play "$work/pods/node-0.yaml" "$subnet_prefix.11"
play "$work/pods/node-1.yaml" "$subnet_prefix.12"
coordinator_exit=$(timeout 180 podman wait "sitlnet-coordinator$suffix-coordinator") || {
  echo "kube_fleet_test: FAILED: the coordinator pod did not end within 180 s" >&2
  podman logs "sitlnet-coordinator$suffix-coordinator" 2>&1 | tail -20 >&2
  exit 1
}
pods_s=$((SECONDS - started_s))
if [[ $coordinator_exit != 0 ]]; then
  echo "kube_fleet_test: FAILED: the coordinator pod exited $coordinator_exit" >&2
  for container in sitlnet-coordinator$suffix-coordinator sitlnet-node-0$suffix-node \
    sitlnet-node-1$suffix-node; do
    echo "--- $container" >&2
    podman logs "$container" 2>&1 | tail -15 >&2
  done
  exit 1
fi

# The reference: the same scenario, every robot on this host.
"$sitlnet" run "$scenario" --one-host --out "$work/one-host" --no-progress 2>"$work/one-host.err" ||
  { echo "kube_fleet_test: FAILED: the one-host run" >&2; cat "$work/one-host.err" >&2; exit 1; }
status=0
for file in trajectories.csv medium.pcap deliveries.csv; do
  if cmp "$work/one-host/$file" "$work/runs/sitlnet-coordinator/run/$file"; then
    echo "kube_fleet_test: $file equal ($(stat -c %s "$work/one-host/$file") B)"
  else
    echo "kube_fleet_test: FAILED: $file differs between the pods and one host" >&2
    status=1
  fi
done

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
echo "kube_fleet_test: pods ran the fleet in ${pods_s} s"
exit $status
