#!/bin/bash
# Makes an images folder whose "flocker" runs the project's flocker as a podman container
# (docs/containers.md; docs/performance.md, "Containers"), for bench/scale/ab.sh:
#
#   sudo bench/containers/flocker_images.sh BUILD OUT_DIR
#   sudo bench/scale/ab.sh BUILD BUILD:OUT_DIR [ROUNDS]       # host flockers vs containers
#
# The image localhost/sitlnet-bench-flocker:latest is built from scripts/container-base's Debian
# 12 base with libprotobuf and BUILD/bin/flocker; remove it with
# `podman rmi localhost/sitlnet-bench-flocker:latest`.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -eq 2 ] || { echo "usage: $0 BUILD OUT_DIR" >&2; exit 2; }
build=$(cd "$1" && pwd) out=$2
base=$("$here/../../scripts/container-base")
context=$(mktemp -d)
trap 'rm -rf "$context"' EXIT
cp "$build/bin/flocker" "$context/flocker"
cat > "$context/Containerfile" <<CONTAINERFILE
FROM $base
RUN apt-get update -qq && apt-get install -y -qq --no-install-recommends libprotobuf32 zlib1g \
    >/dev/null && rm -rf /var/lib/apt/lists/*
COPY flocker /usr/local/bin/flocker
CONTAINERFILE
image=localhost/sitlnet-bench-flocker:latest
podman build -q -t "$image" "$context" >/dev/null
mkdir -p "$out/flocker"
cat > "$out/flocker/image.textproto" <<MANIFEST
# bench/containers/flocker_images.sh: the flocker image as a container
name: "flocker"
container_image: "$image"
command: ["flocker", "--airframe", "\${AIRFRAME}", "\${ARGS}"]
ready_log_line: "t="
MANIFEST
echo "$out"
