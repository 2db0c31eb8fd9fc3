#!/usr/bin/env python3
"""Writes soak.sh's scenario to stdout: a ground station robot (10.77.0.1) and EACH PX4 (system
ids 1..EACH) and EACH ArduCopter (EACH+1..2*EACH) on a 5 m grid, each sending its MAVLink to the
station as the shipped fleet scenarios do; realtime pacing, the clock waits for the robots.

  soak_scenario.py EACH DURATION_S
"""
import sys


def main():
    each, duration_s = int(sys.argv[1]), int(sys.argv[2])
    print('name: "soak"')
    print('robot { name: "gcs" ground_station: true position_m { x: 0 y: -10 z: 2 } }')
    for i in range(2 * each):
        sysid = i + 1
        x, y = 5 * (i % 4), 5 * (i // 4)
        if i < each:
            link = 'px4_sim_port: 4560 image: "px4"'
            args = f'"--gcs", "10.77.0.1", "--sysid", "{sysid}"'
        else:
            link = 'ardupilot_json_port: 9002 image: "arducopter"'
            args = f'"--serial0", "udpclient:10.77.0.1:14550", "--sysid", "{sysid}"'
        print(f'robot {{ name: "uav{sysid}" position_m {{ x: {x} y: {y} z: 0.2 }} {link} args: [{args}] }}')
    print('radio { standard: STANDARD_80211A rate_mbps: 6 }')
    print(f'timing {{ duration_ms: {duration_s * 1000} pacing: PACING_REALTIME wait_for_robots: true }}')


if __name__ == "__main__":
    main()
