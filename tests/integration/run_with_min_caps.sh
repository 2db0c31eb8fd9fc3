#!/usr/bin/env bash
# Runs a test binary holding ONLY CAP_NET_ADMIN and CAP_SYS_ADMIN (every other
# capability dropped from the bounding, inheritable and ambient sets), as a
# container started with `--cap-add NET_ADMIN --cap-add SYS_ADMIN` would.
# Sets SITLNET_MIN_CAPS=1: a check that needs another capability (CAP_NET_RAW,
# CAP_SETUID, CAP_SETPCAP) skips naming it, even under CI=true (test_util.h).
# Usage: run_with_min_caps.sh PROGRAM [args...]   (a test binary, or ctest ...)
# Exit 77 (ctest: skipped) when not root, unless CI=true (then 1).
set -euo pipefail
if [[ $(id -u) -ne 0 ]]; then
  echo "run_with_min_caps: needs root to drop to a chosen capability set" >&2
  [[ "${CI:-}" == "true" ]] && exit 1
  exit 77
fi
caps=-all,+net_admin,+sys_admin
drop=(setpriv --bounding-set="$caps" --inh-caps="$caps" --ambient-caps="$caps" --)
# CAP_NET_ADMIN is bit 12, CAP_SYS_ADMIN bit 21: nothing else may remain.
bounding=$("${drop[@]}" awk '/^CapBnd/ {print $2}' /proc/self/status)
effective=$("${drop[@]}" awk '/^CapEff/ {print $2}' /proc/self/status)
if [[ "$bounding" != "0000000000201000" || "$effective" != "0000000000201000" ]]; then
  echo "run_with_min_caps: could not drop capabilities (CapBnd=$bounding CapEff=$effective)" >&2
  exit 1
fi
echo "run_with_min_caps: CapBnd=$bounding CapEff=$effective (CAP_NET_ADMIN + CAP_SYS_ADMIN only)"
export SITLNET_MIN_CAPS=1
exec "${drop[@]}" "$@"
