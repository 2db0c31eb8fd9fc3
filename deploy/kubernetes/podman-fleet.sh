# Bash functions that play this folder's manifests with podman on one machine, for
# tests/integration/kube_fleet_test.sh, kube_sweep_test.sh and bench/fleet/fleet_pods.sh.
# kube_play_containers_conf WORK: the containers.conf every play here needs. Source it, then:
#   fleet_pods_begin WORK SOURCE_DIR IMAGE SCENARIO NODES  # render, network; sets FLEET_* below
#   fleet_pods_play                                         # the coordinator pod, then the nodes
#   fleet_pods_end                                          # kube down, pods and network removed
# WORK: an empty folder of the caller's; SCENARIO: a file named fleet.textproto whose nodes are
# sitlnet-node-0 .. NODES-1; IMAGE: the packages image the pods run SOURCE_DIR/build in.
# Sets FLEET_COORDINATOR (the coordinator's container), FLEET_NODE_CONTAINERS (array),
# FLEET_RUN_DIR (the central's run folder on this host) and FLEET_NODE_DIRS (the nodes' --out
# folders on this host). Every name carries the suffix -kt<caller's pid>: the cleanup removes
# exactly those. Returns non-zero, its reason on stderr, when a step fails.

# podman 4.3's kube play takes no runtime or ulimit flags: a containers.conf of our own in WORK,
# exported as CONTAINERS_CONF. runc: crun refuses hybrid cgroup hosts. Limits at or below the
# host's hard ones (podman's defaults are above this host's, and a container may not raise them).
kube_play_containers_conf() {  # WORK
  local hard_files
  hard_files=$(ulimit -Hn)
  [[ $hard_files == unlimited ]] && hard_files=1048576
  cat >"$1/containers.conf" <<EOF
[containers]
default_ulimits = ["nofile=$hard_files:$hard_files", "nproc=4096:4096"]
[engine]
runtime = "runc"
EOF
  export CONTAINERS_CONF=$1/containers.conf
}

fleet_pods_begin() {
  FLEET_WORK=$1
  local source_dir=$2 image=$3 scenario=$4
  FLEET_NODES=$5
  FLEET_SUFFIX=-kt$$
  FLEET_NETWORK=sitlnet$FLEET_SUFFIX
  FLEET_SUBNET=10.$((180 + $$ % 60)).$(($$ / 60 % 250))
  FLEET_PLAYED=()
  FLEET_COORDINATOR=sitlnet-coordinator$FLEET_SUFFIX-coordinator
  FLEET_RUN_DIR=$FLEET_WORK/runs/sitlnet-coordinator/run
  FLEET_NODE_CONTAINERS=()
  FLEET_NODE_DIRS=()
  local i
  for ((i = 0; i < FLEET_NODES; i++)); do
    FLEET_NODE_CONTAINERS+=("sitlnet-node-$i$FLEET_SUFFIX-node")
    # The pod's claim, in which the node writes its folder /runs/$(hostname).
    FLEET_NODE_DIRS+=("$FLEET_WORK/runs/sitlnet-node-$i/sitlnet-node-$i")
  done
  head -c 32 /dev/urandom >"$FLEET_WORK/key"
  chmod 600 "$FLEET_WORK/key"
  kube_play_containers_conf "$FLEET_WORK"
  "$source_dir/deploy/kubernetes/render-for-podman" --out "$FLEET_WORK/pods" \
    --suffix="$FLEET_SUFFIX" --image "$image" --checkout "$source_dir" --key "$FLEET_WORK/key" \
    --scenario "$scenario" --runs "$FLEET_WORK/runs" --coordinator-ip "$FLEET_SUBNET.10" \
    --replicas "$FLEET_NODES" >/dev/null || return 1
  podman network create --subnet "$FLEET_SUBNET.0/24" "$FLEET_NETWORK" >/dev/null
}

# kube play of one rendered file at a static address; warnings (e.g. "No more static macs
# left") go to a file, shown if the play fails.
fleet_pods_play_one() {  # FILE IP
  FLEET_PLAYED+=("$1")
  podman kube play --network "$FLEET_NETWORK" --ip "$2" --configmap "$FLEET_WORK/pods/env.yaml" \
    "$1" >/dev/null 2>>"$FLEET_WORK/play.log" || { cat "$FLEET_WORK/play.log" >&2; return 1; }
}

fleet_pods_play() {
  fleet_pods_play_one "$FLEET_WORK/pods/coordinator.yaml" "$FLEET_SUBNET.10" || return 1
  local i
  for ((i = 0; i < FLEET_NODES; i++)); do
    fleet_pods_play_one "$FLEET_WORK/pods/node-$i.yaml" "$FLEET_SUBNET.$((11 + i))" || return 1
  done
}

# The last lines of every container's log, on stderr.
fleet_pods_show_logs() {
  local container
  for container in "$FLEET_COORDINATOR" "${FLEET_NODE_CONTAINERS[@]}"; do
    echo "--- $container" >&2
    podman logs "$container" 2>&1 | tail -15 >&2
  done
}

# kube down of what was played, then every pod and the network by name; never fails.
fleet_pods_end() {
  local file pod i
  for file in "${FLEET_PLAYED[@]}"; do podman kube down "$file" >/dev/null 2>&1 || true; done
  FLEET_PLAYED=()
  for pod in "sitlnet-coordinator$FLEET_SUFFIX" \
    $(for ((i = 0; i < FLEET_NODES; i++)); do echo "sitlnet-node-$i$FLEET_SUFFIX"; done); do
    podman pod rm -f "$pod" >/dev/null 2>&1 || true
  done
  podman network rm "$FLEET_NETWORK" >/dev/null 2>&1 || true
}
