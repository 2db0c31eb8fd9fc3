#!/bin/bash
# scripts/run-on-idle-cpu (docs/view.md, "Watching on the run's own host"): COMMAND runs in a
# cgroup of its own whose cpu.idle is 1, as the kernel's /proc/PID/cgroup and the group's file
# say; its exit status comes back; a process it left behind is ended and the cgroup removed.
# Where this test cannot make a cgroup itself (no root, a read-only cgroup file system: the
# container pass), it checks the script's one-line refusal instead, and says so.
#
#   tests/integration/run_on_idle_cpu_test.sh SOURCE_DIR
set -euo pipefail
script=$1/scripts/run-on-idle-cpu
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Where the script makes its group (the same rule, asked of the host here).
if grep -qw cpu /sys/fs/cgroup/cgroup.subtree_control 2>/dev/null; then
  base=/sys/fs/cgroup
else
  base=$(awk '$3 == "cgroup" && $4 ~ /(^|,)cpu(,|$)/ { print $2; exit }' /proc/mounts)
fi
probe=$base/sitlnet-idle-test-$$
if [ -z "$base" ] || ! mkdir "$probe" 2>/dev/null; then
  status=0
  "$script" true 2> "$work/err" || status=$?
  [ "$status" = 1 ] || fail "exit $status without a cgroup, expected 1"
  grep -q "run-on-idle-cpu: \(this host offers no cgroup cpu controller\|cannot make the cgroup\)" \
    "$work/err" || fail "no refusal line: $(cat "$work/err")"
  echo "no writable cgroup cpu hierarchy here: checked the refusal only"
  exit 0
fi
rmdir "$probe"

# COMMAND: writes its cgroup and that group's cpu.idle, leaves a sleeper behind, exits 3.
status=0
"$script" bash -c '
  group=$(sed -n "s/^[0-9]*:[^:]*\bcpu\b[^:]*:\(.*\)$/\1/p; s/^0::\(.*\)$/\1/p" /proc/self/cgroup | grep sitlnet-idle | head -1)
  echo "$group" > "$1/group"
  cat "$2$group/cpu.idle" > "$1/idle"
  setsid sleep 60 < /dev/null > /dev/null 2>&1 &
  echo $! > "$1/sleeper"
  exit 3' run_on_idle_cpu_test "$work" "$base" || status=$?
[ "$status" = 3 ] || fail "exit $status, expected COMMAND's 3"
group=$(cat "$work/group")
[[ $group == /sitlnet-idle-* ]] || fail "COMMAND ran in cgroup \"$group\", not the script's"
[ "$(cat "$work/idle")" = 1 ] || fail "cpu.idle of $group is $(cat "$work/idle"), expected 1"
# Ended: gone, or a zombie its new parent has not reaped yet.
state=$(sed 's/.*) //' "/proc/$(cat "$work/sleeper")/stat" 2>/dev/null | cut -d' ' -f1 || true)
[ -z "$state" ] || [ "$state" = Z ] || fail "the process COMMAND left is still alive ($state)"
[ ! -e "$base$group" ] || fail "the cgroup $base$group is still there"
echo "COMMAND ran in $base$group (cpu.idle 1), exit 3 came back, its sleeper ended, the group removed"
