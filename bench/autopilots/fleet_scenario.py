#!/usr/bin/env python3
"""Writes an idle fleet of real autopilots on a 3 m grid (bench/autopilots/real_fleet.sh and
where_time_goes.sh).

  fleet_scenario.py KIND N PATH SECONDS PACING [ARG ...]

KIND is px4 or arducopter, PACING LOCKSTEP or REALTIME. Robot i gets args
["--sysid", "i+1"] (both manifests take it), then every ARG (e.g. "--lean",
docs/autopilots.md, "The lean profile").
"""
import sys


def main():
    kind, n, path, seconds, pacing = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4]), sys.argv[5]
    extra = sys.argv[6:]
    side = int(n ** 0.5 + 0.999)
    with open(path, "w") as f:
        f.write('name: "rabench"\naddresses { wlan_subnet: "10.68.0.0/16" ctl_subnet: "10.69.0.0/16" }\n')
        for i in range(n):
            x, y = 3 * (i % side), 3 * (i // side)
            link = 'px4_sim_port: 4560 image: "px4"' if kind == "px4" else \
                   'ardupilot_json_port: 9002 image: "arducopter"'
            args = ", ".join(f'"{a}"' for a in ["--sysid", str(i + 1)] + extra)
            f.write(f'robot {{ name: "r{i}" position_m {{ x: {x} y: {y} z: 0.2 }} {link} args: [{args}] }}\n')
        f.write(f"timing {{ duration_ms: {seconds * 1000} pacing: PACING_{pacing} }}\n")


if __name__ == "__main__":
    main()
