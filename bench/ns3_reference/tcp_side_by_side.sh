#!/bin/bash
# TCP or UDP between two robots, sitlnet's medium and ns-3's TapBridge side by
# side in one run: the same two namespaces (sitlnet up), the same unmodified
# iperf3 flow, the medium in between alternated (sitlnet medium, then ns-3,
# then ns-3, then sitlnet, ... : ABBA rounds, so a drift of the host's load
# falls on both). Ad hoc, two robots DISTANCE m apart (10: a clean channel).
# RADIO: an 802.11a rate in Mb/s (default 54), or 802.11n at 5 GHz, 20 MHz, long
# guard interval: ht-mcsM (no A-MPDU) or ht-mcsM-ampdu (radio.aggregation: true;
# ns-3's A-MPDU defaults); or 802.11ac, long guard interval: vht-mcsM-WIDTH or
# vht-mcsM-WIDTH-ampdu (best effort's A-MPDU limit at VHT's maximum, 1048575 B, on
# both sides: 64 MPDUs; the robots 1 m apart, where VHT MCS 9 loses nothing).
# PROTOCOL: tcp (default) or udp (iperf3 -u -l 1470 -b 100M, 600M for 802.11ac:
# more than either medium carries; the receiver's goodput). Prints one row
# per run, then the medians and their ratio; writes the rows to
# <build-dir>/ns3_<protocol>[_<radio>].csv. Needs root; installs Debian's
# libns3-dev and ns3 (TapBridge's TAP opener) if missing.
# Usage: bench/ns3_reference/tcp_side_by_side.sh [build-dir] [rounds] [seconds] [radio] [protocol]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
rounds=${2:-4}
seconds=${3:-10}
radio=${4:-54}
protocol=${5:-tcp}
distance_m=10
scenario=n3tcp
if [ "$(id -u)" != 0 ]; then
  echo "tcp_side_by_side.sh: needs root (namespaces, TAPs, the medium daemon)" >&2
  exit 3
fi
missing=""
for package in libns3-dev ns3; do
  dpkg -s "$package" > /dev/null 2>&1 || missing="$missing $package"
done
if [ -n "$missing" ]; then
  apt-get update > /dev/null
  apt-get install -y --no-install-recommends $missing > /dev/null
fi
# A build directory of the user's keeps its build type; a new one is Release.
if [ -f "$build/CMakeCache.txt" ]; then
  cmake -S "$repo" -B "$build" > /dev/null
else
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
fi
cmake --build "$build" -j2 --target ns3_tap_bridge sitlnet > /dev/null
sitlnet=$build/bin/sitlnet
if [ -e "/run/sitlnet/$scenario" ]; then
  echo "tcp_side_by_side.sh: scenario $scenario is already up (sitlnet down $scenario)" >&2
  exit 1
fi

work=$(mktemp -d)
bridge_pid=""
server_pid=""
cleanup() {
  for pid in $server_pid $bridge_pid; do kill -TERM "$pid" 2> /dev/null || true; done
  for pid in $server_pid $bridge_pid; do wait "$pid" 2> /dev/null || true; done
  "$sitlnet" down "$scenario" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT
udp_rate=100M
case $radio in
  ht-mcs[0-7]) radio_line="radio { standard: STANDARD_80211N_5GHZ mcs: ${radio#ht-mcs} channel_width_mhz: 20 }" ;;
  ht-mcs[0-7]-ampdu)
    mcs=${radio#ht-mcs}
    radio_line="radio { standard: STANDARD_80211N_5GHZ mcs: ${mcs%-ampdu} channel_width_mhz: 20 aggregation: true }" ;;
  vht-mcs[0-9]-20 | vht-mcs[0-9]-40 | vht-mcs[0-9]-80 | vht-mcs[0-9]-20-ampdu | vht-mcs[0-9]-40-ampdu | vht-mcs[0-9]-80-ampdu)
    IFS=- read -r _ mcs width ampdu <<< "$radio"
    radio_line="radio { standard: STANDARD_80211AC mcs: ${mcs#mcs} channel_width_mhz: $width"
    [ -n "$ampdu" ] && radio_line="$radio_line aggregation: true ampdu_max_bytes_be: 1048575"
    radio_line="$radio_line }"
    distance_m=1
    udp_rate=600M ;;
  *) radio_line="radio { standard: STANDARD_80211A rate_mbps: $radio }" ;;
esac
case $protocol in
  tcp) flow=() ;;
  udp) flow=(-u -b "$udp_rate" -l 1470) ;;
  *) echo "tcp_side_by_side.sh: protocol $protocol: want tcp or udp" >&2; exit 2 ;;
esac
cat > "$work/$scenario.textproto" << EOF
name: "$scenario"
robot { name: "a" position_m { x: 0 y: 0 z: 1 } }
robot { name: "b" position_m { x: $distance_m y: 0 z: 1 } }
$radio_line
EOF
"$sitlnet" up "$work/$scenario.textproto" > /dev/null
server_address=$(ip -n "$scenario-b" -4 -o addr show wlan0 | awk '{print $4}' | cut -d/ -f1)

# Reads lines of the file descriptor $1 until one contains $2 (10 s at most).
await_line() {
  local line
  while IFS= read -r -t 10 line <&"$1"; do
    [[ $line == *"$2"* ]] && return 0
  done
  echo "tcp_side_by_side.sh: no \"$2\" within 10 s" >&2
  return 1
}

# One measurement with medium $1 (sitlnet or ns3): writes "goodput_mbps retransmits"
# to $work/result.
measure() {
  local side=$1 ready
  rm -f "$work/out.fifo"
  mkfifo "$work/out.fifo"
  if [ "$side" = sitlnet ]; then
    "$sitlnet" medium "$scenario" > /dev/null 2> "$work/out.fifo" &
    ready="robots attached"
  else
    chrt -f 10 "$build/bin/ns3_tap_bridge" "$scenario-a" "$scenario-b" "$distance_m" "$radio" \
      > "$work/out.fifo" 2>&1 &
    ready="ready"
  fi
  bridge_pid=$!
  exec {from_bridge}< "$work/out.fifo"
  await_line "$from_bridge" "$ready"
  cat <&"$from_bridge" > "$work/$side.log" &
  local drain_pid=$!
  exec {from_bridge}<&-

  rm -f "$work/server.fifo"
  mkfifo "$work/server.fifo"
  "$sitlnet" exec "$scenario-b" -- iperf3 -s -1 --forceflush -B "$server_address" \
    > "$work/server.fifo" 2>&1 &
  server_pid=$!
  exec {from_server}< "$work/server.fifo"
  await_line "$from_server" "Server listening"
  cat <&"$from_server" > /dev/null &
  exec {from_server}<&-
  "$sitlnet" exec "$scenario-a" -- iperf3 -c "$server_address" "${flow[@]}" -t "$seconds" -O 1 --json \
    > "$work/client.json"
  wait "$server_pid"
  server_pid=""

  kill -TERM "$bridge_pid"
  wait "$bridge_pid"
  bridge_pid=""
  wait "$drain_pid"
  [ -n "${TCP_SIDE_BY_SIDE_LOGS:-}" ] && cp "$work/$side.log" "$TCP_SIDE_BY_SIDE_LOGS/$side.log"
  # UDP: what the server received (its report, in the client's JSON); TCP has no datagram losses.
  python3 -c '
import json, sys
end = json.load(open(sys.argv[1]))["end"]
if "sum_received" in end:
    print("%.3f %d" % (end["sum_received"]["bits_per_second"] / 1e6,
                       end["sum_sent"].get("retransmits", 0)))
else:
    s = end["sum"]
    print("%.3f 0" % ((s["packets"] - s["lost_packets"]) * 1470 * 8 / s["seconds"] / 1e6))
' "$work/client.json" > "$work/result"
}

csv=$build/ns3_$protocol.csv
[ "$radio" != 54 ] && csv=$build/ns3_${protocol}_$radio.csv
{
  echo "# $protocol between two robots (iperf3 $seconds s, first second omitted), radio $radio," \
    "$distance_m m: sitlnet medium vs ns-3 $(dpkg-query -W -f='${Version}' libns3-dev) TapBridge"
  echo "# sitlnet at commit $(git -C "$repo" rev-parse --short HEAD 2> /dev/null || echo unknown);" \
    "started $(date -u +%FT%TZ), load average $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "round,medium,goodput_mbps,retransmits"
} > "$csv"
for round in $(seq 1 "$rounds"); do
  if [ $((round % 2)) = 1 ]; then order="sitlnet ns3"; else order="ns3 sitlnet"; fi
  for side in $order; do
    measure "$side"
    read -r goodput retransmits < "$work/result"
    echo "$round,$side,$goodput,$retransmits" | tee -a "$csv"
  done
done
python3 - "$csv" << 'EOF'
import csv, statistics, sys
rows = [r for r in csv.reader(l for l in open(sys.argv[1]) if not l.startswith("#"))][1:]
by = {}
for _, medium, goodput, retransmits in rows:
    by.setdefault(medium, []).append((float(goodput), int(retransmits)))
for medium, runs in by.items():
    g = [x for x, _ in runs]
    print("%-8s median %.3f Mb/s (%.3f-%.3f), retransmits %s"
          % (medium, statistics.median(g), min(g), max(g), [r for _, r in runs]))
ratio = statistics.median(x for x, _ in by["sitlnet"]) / statistics.median(x for x, _ in by["ns3"])
print("sitlnet / ns-3 goodput: %.4f (%+.2f %%)" % (ratio, (ratio - 1) * 100))
EOF
echo "rows in $csv"
