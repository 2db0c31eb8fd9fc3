#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) in build-fuzz/ and runs each for
# SECONDS (default 10), as many at a time as there are cores, from its committed seed corpus
# fuzz/corpus/<target>/. New inputs go to build-fuzz/corpus/<target>/ (not committed); crashes
# to build-fuzz/artifacts/<target>/.
# Exit status 1 if any target found a crash, leak or timeout (its log is printed).
# Usage: fuzz/run.sh [SECONDS] [TARGET...]     long run: fuzz/run.sh 3600 medium_frame_fuzz
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-10}"
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scenario_text_fuzz motor_command_fuzz servo_packet_fuzz
  coordinator_frame_fuzz medium_frame_fuzz image_manifest_fuzz state_file_fuzz
  remote_medium_reply_fuzz remote_medium_request_fuzz control_socket_fuzz node_to_central_fuzz
  central_to_node_fuzz)

build=build-fuzz
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSITLNET_FUZZ=ON \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  >"/tmp/sitlnet-build-fuzz.configure.log" 2>&1 || { cat "/tmp/sitlnet-build-fuzz.configure.log" >&2; exit 1; }
mkdir -p "$build"
cmake --build "$build" -j2 --target ubsan_canary_fuzz "${targets[@]}" >"$build/build.log" 2>&1 ||
  { tail -50 "$build/build.log" >&2; exit 1; }

# Undefined behaviour must fail a run, not print and pass: the canary overflows an int on "UB".
canary=$(mktemp -d)
trap 'rm -rf "$canary"' EXIT
printf 'UB' >"$canary/input"
if "$build/fuzz/ubsan_canary_fuzz" "$canary/input" >"$canary/log" 2>&1 ||
    ! grep -q 'runtime error: signed integer overflow' "$canary/log"; then
  echo "fuzz: a UBSan report did not fail the run (build flags?):" >&2
  cat "$canary/log" >&2
  exit 1
fi
echo "fuzz: ubsan_canary_fuzz fails on undefined behaviour, as it must"

# One target: its verdict goes to $build/logs/<target>.verdict (ok or failed).
fuzz_one() {
  local target=$1
  mkdir -p "$build/corpus/$target" "$build/artifacts/$target" "$build/logs"
  local log="$build/logs/$target.log"
  # -rss_limit_mb: the decoders bound their allocations far below this; -timeout: no input
  # may take a second.
  if "$build/fuzz/$target" -max_total_time="$seconds" -timeout=1 -rss_limit_mb=1024 \
      -print_final_stats=1 -artifact_prefix="$build/artifacts/$target/" \
      "$build/corpus/$target" "fuzz/corpus/$target" >"$log" 2>&1; then
    runs=$(grep -oE 'stat::number_of_executed_units: *[0-9]+' "$log" | grep -oE '[0-9]+$' || echo '?')
    echo "fuzz: $target ok, $runs inputs in ${seconds} s"
    echo ok >"$build/logs/$target.verdict"
  else
    echo "fuzz: $target FAILED (log $log, inputs in $build/artifacts/$target/):" >&2
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$log" | head -20 >&2
    echo failed >"$build/logs/$target.verdict"
  fi
}

# One target per core at a time: each is single-threaded.
mkdir -p "$build/logs"
for target in "${targets[@]}"; do
  rm -f "$build/logs/$target.verdict"
  while (($(jobs -rp | wc -l) >= $(nproc))); do wait -n || true; done
  fuzz_one "$target" &
done
wait
failed=()
for target in "${targets[@]}"; do
  [[ $(cat "$build/logs/$target.verdict" 2>/dev/null) == ok ]] || failed+=("$target")
done
((${#failed[@]} == 0)) || { echo "fuzz: failures in ${failed[*]}" >&2; exit 1; }
