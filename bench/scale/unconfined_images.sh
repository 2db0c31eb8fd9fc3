#!/bin/bash
# Copies robot_images/ to DIR with `sandbox: NONE` added to every manifest: the images as they
# ran before the robot sandbox, for bench/scale/ab.sh BUILD:DIR BUILD (docs/performance.md).
#
#   bench/scale/unconfined_images.sh DIR
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 DIR" >&2; exit 2; }
src=$(cd "$(dirname "$0")/../../robot_images" && pwd)
mkdir -p "$1"
cp -r "$src"/. "$1"/
for manifest in "$1"/*/image.textproto; do
  echo 'sandbox: NONE' >> "$manifest"
done
