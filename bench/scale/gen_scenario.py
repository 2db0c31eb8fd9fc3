#!/usr/bin/env python3
"""Writes the scaled flocking scenario for N robots (bench/scale).

N robots = ceil(N/4) replicas of the 4-robot case study side by side along y,
50 m apart, so the obstacle count grows with the area and the robot density
stays that of the case study. The replicas are read from the case study's own
file, scenarios/arrow_flocking.textproto: its robot blocks (start positions,
image, flocker args, lidar) and obstacle blocks (the arrow: nine head boxes
and the shaft, 27 m wide at most), each shifted by the replica's y offset y0;
a robot's --target moves with its replica (x, y + y0), so every replica flies
as the case study does. The last replica takes the first N mod 4 robots when
N is not a multiple of 4. With one replica (N <= 4) names, positions, args and
obstacles are the case study's exactly; with several, obstacle names get a
"_r<replica>" suffix and robots are uav1..uavN.

Robots of neighbouring replicas start 46 m apart at the closest (the case
study's robots are at y = +-2), inside the 51 m line-of-sight detection range
of the case study's radio (docs/case-study.md), so the medium sees one
connected fleet at the start, not N/4 isolated ones.

Usage: gen_scenario.py N OUT.textproto [--no-obstacles]
(--no-obstacles: the same fleet without the arrows, to measure what they cost)
"""
import math
import os
import re
import sys

REPLICA_PITCH_M = 50.0
CASE_STUDY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenarios",
                          "arrow_flocking.textproto")


def strip_comments(text):
    """The text without its '#' comments (a '#' inside a quoted string is kept)."""
    out = []
    for line in text.splitlines():
        quoted = False
        for i, c in enumerate(line):
            if c == '"' and (i == 0 or line[i - 1] != "\\"):
                quoted = not quoted
            elif c == "#" and not quoted:
                line = line[:i]
                break
        out.append(line)
    return "\n".join(out)


def top_level_blocks(text):
    """[(field, body)] for every top-level `field { body }` of a text-format message."""
    blocks = []
    pos = 0
    opening = re.compile(r"\s*([A-Za-z_]\w*)\s*:?\s*\{")
    scalar = re.compile(r"\s*[A-Za-z_]\w*\s*:\s*(\"[^\"]*\"|[^\s{}]+)")
    while pos < len(text):
        if not text[pos:].strip():
            break
        m = opening.match(text, pos)
        if not m:
            s = scalar.match(text, pos)
            if not s:
                raise ValueError(f"cannot parse the case study near: {text[pos:pos + 40]!r}")
            pos = s.end()
            continue
        depth, i, quoted = 1, m.end(), False
        while depth:
            if i >= len(text):
                raise ValueError(f"unbalanced braces in the case study's {m.group(1)} block")
            c = text[i]
            if c == '"' and text[i - 1] != "\\":
                quoted = not quoted
            elif not quoted and c == "{":
                depth += 1
            elif not quoted and c == "}":
                depth -= 1
            i += 1
        blocks.append((m.group(1), text[m.end():i - 1]))
        pos = i
    return blocks


def shift_vector(body, field, dy):
    """`body` with the y of its `field { x: .. y: .. z: .. }` increased by dy (y absent = 0)."""
    m = re.search(field + r"\s*:?\s*\{([^}]*)\}", body)
    if not m:
        raise ValueError(f"no {field} in a case-study block")
    values = dict(re.findall(r"([xyz])\s*:\s*([-+0-9.eE]+)", m.group(1)))
    for axis in values:
        values[axis] = float(values[axis])
    values["y"] = values.get("y", 0.0) + dy
    inner = " ".join(f"{axis}: {values[axis]:g}" for axis in "xyz" if axis in values)
    return body[:m.start()] + f"{field} {{ {inner} }}" + body[m.end():]


def rename(body, name):
    return re.sub(r'(?<![\w.])name\s*:\s*"[^"]*"', f'name: "{name}"', body, count=1)


def shift_target(body, dy):
    """`body` with the y of its flocker `--target X,Y` argument increased by dy."""
    def moved(m):
        x, y = (float(v) for v in m.group(2).split(","))
        return f'{m.group(1)}"{x:g},{y + dy:g}"'
    return re.sub(r'("--target"\s*,\s*)"([^"]*)"', moved, body)


def one_line(body):
    return " ".join(body.split())


def read_case_study(path=CASE_STUDY):
    """(robot bodies, obstacle bodies, radio body) of the case study, in file order."""
    with open(path, encoding="utf-8") as f:
        blocks = top_level_blocks(strip_comments(f.read()))
    robots = [body for field, body in blocks if field == "robot"]
    obstacles = [body for field, body in blocks if field == "obstacle"]
    radios = [body for field, body in blocks if field == "radio"]
    if len(robots) != 4 or not obstacles or len(radios) != 1:
        raise ValueError(f"{path}: expected 4 robots, obstacles and one radio block")
    return robots, obstacles, radios[0]


def scenario(n, obstacles=True):
    robots, boxes, radio = read_case_study()
    replicas = max(1, math.ceil(n / len(robots)))
    lines = [
        f"# Generated by bench/scale/gen_scenario.py {n}: {replicas} replica(s) of the",
        "# arrow case study (scenarios/arrow_flocking.textproto), 50 m apart along y.",
        f'name: "scale{n}"',
        # Own subnets so that the benchmark never collides with the defaults
        # another engineer's scenario uses; /24 holds 253 robots, /16 ctl.
        'addresses { wlan_subnet: "10.93.0.0/24" ctl_subnet: "10.94.0.0/16" }',
    ]
    for i in range(n):
        r, k = divmod(i, len(robots))
        y0 = REPLICA_PITCH_M * (r - (replicas - 1) / 2)
        body = shift_target(shift_vector(rename(robots[k], f"uav{i + 1}"), "position_m", y0), y0)
        lines.append(f"robot {{ {one_line(body)} }}")
    for r in range(replicas if obstacles else 0):
        y0 = REPLICA_PITCH_M * (r - (replicas - 1) / 2)
        for box in boxes:
            body = shift_vector(box, "center_m", y0)
            if replicas > 1:
                name = re.search(r'(?<![\w.])name\s*:\s*"([^"]*)"', box)
                body = rename(body, f"{name.group(1) if name else 'box'}_r{r}")
            lines.append(f"obstacle {{ {one_line(body)} }}")
    lines += [
        f"radio {{ {one_line(radio)} }}",
        "timing { duration_ms: 130000 iteration_us: 10000 physics_step_us: 1000"
        " network_step_us: 10000 }",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4) or sys.argv[3:] not in ([], ["--no-obstacles"]):
        sys.exit("usage: gen_scenario.py N OUT.textproto [--no-obstacles]")
    n = int(sys.argv[1])
    if not 1 <= n <= 253:
        sys.exit("gen_scenario.py: N must be 1..253 (wlan /24)")
    with open(sys.argv[2], "w") as out:
        out.write(scenario(n, obstacles=len(sys.argv) == 3))
