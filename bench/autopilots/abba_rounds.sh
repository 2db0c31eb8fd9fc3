# Sourced by the A/B benches (harness_ab.sh, real_fleet_ab.sh): ROUNDS rounds over every size in
# SIZES and kind in KINDS; round r calls `run old OLD KIND N` then `run new NEW KIND N` if r is
# odd, the other order if even, so a noisy minute of the shared host falls on both builds. The
# caller defines run LABEL BUILD KIND N.
abba_rounds() {  # ROUNDS SIZES KINDS OLD NEW
  local rounds=$1 sizes=$2 kinds=$3 old=$4 new=$5 r n kind
  for r in $(seq 1 "$rounds"); do
    for n in $sizes; do
      for kind in $kinds; do
        if (( r % 2 )); then run old "$old" "$kind" "$n"; run new "$new" "$kind" "$n"
        else run new "$new" "$kind" "$n"; run old "$old" "$kind" "$n"; fi
      done
    done
  done
}
