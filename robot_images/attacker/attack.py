#!/usr/bin/python3
"""sitlnet's attacker image: tries each way out of a robot and reports what worked.

One line per attempt on stdout: "attack NAME: blocked (why)" or "attack NAME: ESCAPED (how)",
then "attacks done". Whatever an attempt changes on the host is undone at once (a route, an
address, a file it managed to write). The attempt "survive_teardown" leaves a process named
"sv-<scenario>" asleep: only the harness that tore the robot down can tell whether it is still
alive (docs/security.md).
"""
import ctypes
import os
import socket
import subprocess
import sys
import time

CLONE_NEWNS = 0x00020000
CLONE_NEWPID = 0x20000000
MS_REC = 0x4000
MS_PRIVATE = 1 << 18
PR_SET_NAME = 15

libc = ctypes.CDLL(None, use_errno=True)
SCENARIO = os.environ.get("SITLNET_SCENARIO", "")


def report(name, escaped, detail):
    print(f"attack {name}: {'ESCAPED' if escaped else 'blocked'} ({detail})", flush=True)


def in_child(action):
    """Runs action() in a forked child (so that namespace changes stay there); its result."""
    pid = os.fork()
    if pid == 0:
        try:
            os._exit(0 if action() else 1)
        except BaseException:  # noqa: BLE001 - any failure is "did not work"
            os._exit(2)
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status) == 0


def host_processes():
    """A visible process of another network namespace (the host's), or None."""
    own = os.readlink("/proc/self/ns/net")
    for entry in [str(os.getppid())] + sorted(os.listdir("/proc")):
        if not entry.isdigit():
            continue
        try:
            net = os.readlink(f"/proc/{entry}/ns/net")
        except OSError:
            continue
        if net != own:
            report("host_processes", True, f"pid {entry} is in another network namespace")
            return int(entry)
    report("host_processes", False, "every visible process is in this robot")
    return None


def enter_other_namespace(target):
    """setns to the network namespace of `target` (a host process), of PID 1, or of any robot
    named in /run/netns."""
    own = os.readlink("/proc/self/ns/net")
    candidates = [f"/proc/{target or 1}/ns/net"]
    try:
        candidates += [f"/run/netns/{name}" for name in sorted(os.listdir("/run/netns"))]
    except OSError:
        pass

    def enter(path):
        fd = os.open(path, os.O_RDONLY)
        return libc.setns(fd, 0) == 0 and os.readlink("/proc/self/ns/net") != own

    for path in candidates:
        if in_child(lambda: enter(path)):
            report("enter_other_namespace", True, f"setns to {path}")
            return
    report("enter_other_namespace", False, f"setns refused or no way out: {', '.join(candidates)}")


def open_path(name, path, mode="r"):
    try:
        with open(path, mode) as handle:
            if "r" in mode:
                handle.read(1)
        report(name, True, f"opened {path}")
        return True
    except OSError as error:
        report(name, False, f"{path}: {error.strerror}")
        return False


def list_robot_namespaces():
    try:
        names = os.listdir("/run/netns")
    except OSError as error:
        report("list_robot_namespaces", False, f"/run/netns: {error.strerror}")
        return
    report("list_robot_namespaces", bool(names), f"/run/netns lists {len(names)}")


def connect_control_sockets():
    folder = f"/run/sitlnet/{SCENARIO}"
    try:
        sockets = [f"{folder}/{n}" for n in os.listdir(folder) if n.endswith(".sock")]
    except OSError as error:
        report("connect_control_socket", False, f"{folder}: {error.strerror}")
        return
    for path in sockets:
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as unix:
            try:
                unix.connect(path)
                report("connect_control_socket", True, f"connected to {path}")
                return
            except OSError:
                pass
    report("connect_control_socket", False,
           f"{len(sockets)} sockets in {folder}, none accepted a connection")


def write_run_folder():
    log = os.readlink("/proc/self/fd/1")
    target = os.path.join(os.path.dirname(log), "attack-was-here")
    if open_path("write_run_folder", target, "w"):
        os.unlink(target)


def write_host_sysctl():
    path = "/proc/sys/vm/overcommit_ratio"
    try:
        with open(path) as handle:
            value = handle.read()
        with open(path, "w") as handle:  # The same value back: harmless if it works.
            handle.write(value)
        report("write_host_sysctl", True, f"wrote {path}")
    except OSError as error:
        report("write_host_sysctl", False, f"{path}: {error.strerror}")


def mount_filesystem():
    def mount():
        if libc.unshare(CLONE_NEWNS) != 0:
            return False
        # Private first, so that nothing propagates to the host's mounts if this works.
        if libc.mount(None, b"/", None, MS_REC | MS_PRIVATE, None) != 0:
            return False
        return libc.mount(b"none", b"/mnt", b"tmpfs", 0, None) == 0

    worked = in_child(mount)
    report("mount_filesystem", worked, "tmpfs on /mnt" if worked else "unshare or mount refused")


def ip_change(name, add, delete):
    result = subprocess.run(["ip"] + add, capture_output=True, text=True)
    if result.returncode == 0:
        subprocess.run(["ip"] + delete, capture_output=True)
        report(name, True, "ip " + " ".join(add))
    else:
        report(name, False, result.stderr.strip() or f"ip exit {result.returncode}")


def reach_host_via_ctl0():
    """Another address beyond ctl0, with the neighbour table written by hand (which needs
    CAP_NET_ADMIN): the next robot's ctl0 root side, a local address of the scenario's ctl
    namespace (of the host's, before that namespace). A TCP connection there that is refused
    (nothing listens) or accepted reached it; a timeout did not."""
    own = os.environ.get("SITLNET_PHYSICS_ADDR", "").split(":")[0]
    if not own:
        report("reach_host_via_ctl0", False, "no SITLNET_PHYSICS_ADDR")
        return
    octets = own.split(".")
    target = ".".join(octets[:3] + [str(int(octets[3]) + 4)])
    # The root side's MAC, learnt by ARP for a datagram to its own address (any port).
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as udp:
        udp.sendto(b"x", (own, 9))
    neighbour = []
    for _ in range(20):
        neighbour = subprocess.run(["ip", "neigh", "show", own, "dev", "ctl0"],
                                   capture_output=True, text=True).stdout.split()
        if "lladdr" in neighbour:
            break
        time.sleep(0.1)
    if "lladdr" not in neighbour:
        report("reach_host_via_ctl0", False, f"no MAC learnt for {own}")
        return
    mac = neighbour[neighbour.index("lladdr") + 1]
    changes = [["route", "add", f"{target}/32", "dev", "ctl0"],
               ["neigh", "replace", target, "lladdr", mac, "dev", "ctl0", "nud", "permanent"]]
    for change in changes:
        result = subprocess.run(["ip"] + change, capture_output=True, text=True)
        if result.returncode != 0:
            report("reach_host_via_ctl0", False, f"ip {change[0]}: {result.stderr.strip()}")
            return
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as tcp:
        tcp.settimeout(2)
        try:
            tcp.connect((target, 9))
            outcome = (True, f"connected to {target}:9")
        except ConnectionRefusedError:
            outcome = (True, f"{target}:9 answered (refused)")
        except OSError as error:
            outcome = (False, f"{target}:9: {error.strerror or 'timed out'}")
    subprocess.run(["ip", "route", "del", f"{target}/32", "dev", "ctl0"], capture_output=True)
    report("reach_host_via_ctl0", *outcome)


def leave_cgroup():
    """Moves a child into the root cgroup of each hierarchy it can see, out of the robot's (whose
    limits, accounting and kill then no longer reach it)."""
    import glob

    targets = sorted(glob.glob("/sys/fs/cgroup/cgroup.procs") +
                     glob.glob("/sys/fs/cgroup/*/cgroup.procs"))

    def move(path):
        with open(path, "w") as handle:
            handle.write("0")
        return True

    for path in targets:
        if in_child(lambda: move(path)):
            report("leave_cgroup", True, f"joined {path}")
            return
    report("leave_cgroup", False, f"{len(targets)} cgroup.procs files, none took the process")


def raw_sockets():
    opened = []
    for family, kind, protocol, what in (
        (socket.AF_INET6, socket.SOCK_RAW, socket.IPPROTO_ICMPV6, "raw ICMPv6 (router adverts)"),
        (socket.AF_INET, socket.SOCK_RAW, socket.IPPROTO_UDP, "raw IPv4 (spoofed sources)"),
        (socket.AF_PACKET, socket.SOCK_RAW, 0, "packet socket (forged frames)"),
    ):
        try:
            socket.socket(family, kind, protocol).close()
            opened.append(what)
        except OSError:
            pass
    report("raw_sockets", bool(opened), ", ".join(opened) or "every raw socket refused")


def survive_teardown():
    name = f"sv-{SCENARIO}"[:15]
    # The survivor says when it bears its name: until then the harness could not find it, and
    # this robot must not end before (on a busy host the grandchild may run late).
    named_read, named_write = os.pipe()
    if os.fork() == 0:
        os.setsid()
        if os.fork() == 0:
            os.close(named_read)
            libc.unshare(CLONE_NEWPID | CLONE_NEWNS)  # Refused in the sandbox; tried anyway.
            libc.prctl(PR_SET_NAME, name.encode(), 0, 0, 0)
            os.write(named_write, b"n")
            os.close(named_write)
            devnull = os.open("/dev/null", os.O_RDWR)
            for fd in (0, 1, 2):
                os.dup2(devnull, fd)
            while True:
                os.pause()
        os._exit(0)
    os.close(named_write)
    os.read(named_read, 1)
    os.close(named_read)
    os.wait()
    print(f"attack survive_teardown: left process {name}", flush=True)


def main():
    enter_other_namespace(host_processes())
    open_path("read_state_file", f"/run/sitlnet/{SCENARIO}/state")
    list_robot_namespaces()
    connect_control_sockets()
    write_run_folder()
    if open_path("write_host_file", "/etc/sitlnet-attack-was-here", "w"):
        os.unlink("/etc/sitlnet-attack-was-here")
    write_host_sysctl()
    mount_filesystem()
    ip_change("route_via_ctl0", ["route", "add", "192.0.2.1/32", "dev", "ctl0"],
              ["route", "del", "192.0.2.1/32", "dev", "ctl0"])
    ip_change("spoof_ctl0_address", ["address", "add", "192.0.2.77/32", "dev", "ctl0"],
              ["address", "del", "192.0.2.77/32", "dev", "ctl0"])
    raw_sockets()
    reach_host_via_ctl0()
    leave_cgroup()
    survive_teardown()
    print("attacks done", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
