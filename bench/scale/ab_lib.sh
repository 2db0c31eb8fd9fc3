# Functions for the A/B benchmarks of one build with and without a feature (losses_ab.sh,
# view_ab.sh): sourced, not run. Each variant flies the same scale scenario (gen_scenario.py),
# lockstep, with the round's seed; the order of the variants is reversed every round (ABBA: a
# noisy minute on a shared host falls on all of them).
#
# The sourcing script defines three hooks, then calls ab_series:
#   ab_args VARIANT         the variant's extra `sitlnet run` arguments, one a line
#   ab_while VARIANT DIR PID   runs while the run (PID, folder DIR, log DIR.log) goes, e.g. a
#                           client of its live view; its output is kept in DIR.while
#   ab_after VARIANT DIR    after the run, before DIR is removed: prints the row's extra
#                           columns (EXTRA_HEADER names them), from DIR and DIR.while

# ab_series BUILD OUT N SECONDS ROUNDS "VARIANT..." EXTRA_HEADER: runs the rounds, one row per
# run into OUT/runs.csv (variant, extract.py's columns, then ab_after's), and each run's log
# lines matching "live view:" into OUT/cost_lines.txt. Logs and DIR.while files stay in OUT.
# With AB_UNTIL set (a time `date -d` reads), no round starts after it: a measurement fits a
# quiet window of the host.
ab_series() {
  local build=$1 out=$2 n=$3 seconds=$4 rounds=$5 variants=$6 extra_header=$7
  local here round order variant dir load1 start run wall args
  here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
  mkdir -p "$out"
  "$here/gen_scenario.py" "$n" "$out/scale.textproto"
  echo "variant,$("$here/extract.py" --header),$extra_header" > "$out/runs.csv"
  for round in $(seq 1 "$rounds"); do
    if [ -n "${AB_UNTIL:-}" ] && [ "$(date +%s)" -ge "$(date -d "$AB_UNTIL" +%s)" ]; then
      echo "ab_series: $AB_UNTIL passed, $((round - 1)) rounds run" >&2
      break
    fi
    order=$variants
    [ $((round % 2)) = 0 ] && order=$(echo "$variants" | tr ' ' '\n' | tac | tr '\n' ' ')
    for variant in $order; do
      dir="$out/$variant-$round"
      load1=$(cut -d' ' -f1 /proc/loadavg)
      : > "$dir.log"  # ab_while may read it before the run has opened it.
      start=$(date +%s%N)
      mapfile -t args < <(ab_args "$variant")
      "$build/bin/sitlnet" run "$out/scale.textproto" --out "$dir" --pacing lockstep \
        --duration "$seconds" --seed "$round" --no-progress "${args[@]}" > "$dir.log" 2>&1 &
      run=$!
      ab_while "$variant" "$dir" "$run" > "$dir.while"
      wait "$run"
      wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
      echo "$variant,$("$here/extract.py" "$dir" "$n" lockstep "$round" "$wall" "$load1"),$(ab_after "$variant" "$dir")" \
        >> "$out/runs.csv"
      grep "live view:" "$dir.log" | sed "s/^/$variant-$round: /" >> "$out/cost_lines.txt" || true
      rm -rf "$dir"
    done
  done
}

# ab_view_url LOG PID: the live view's URL once the run (PID) has printed it in LOG (the server
# binds before the run starts), or nothing if the run ended first.
ab_view_url() {
  local log=$1 pid=$2 url=""
  while [ -z "$url" ] && kill -0 "$pid" 2>/dev/null; do
    url=$(sed -n 's/^sitlnet run: live view at //p' "$log")
    [ -n "$url" ] || sleep 0.05
  done
  echo "$url"
}
