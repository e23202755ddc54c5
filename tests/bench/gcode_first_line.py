#!/usr/bin/env python3
"""Time to a G-code file's first line, and the host's peak memory, for a small and a large file.

Each host prints FILE to a pseudo-terminal whose other end is a stand-in firmware here that
answers every line with `ok` at once (no pacing; no banner, as a board on native USB that does
not reset when its port opens; with boot_s > 0, a board that does: it loses what it is sent for
boot_s seconds from the host's start, then says `start`): the time from starting the host
to the arrival of the file's first command (after the host's own handshake lines), and the
host's peak resident memory (VmHWM) once it has streamed for `stream_s` seconds more. The
hosts are `mahost print FILE --port PTY` and Printrun's `printcore PTY FILE`, alternated,
`rounds` times each, medians; beside the time to the first line, the CPU time the host used
until then (what a loaded machine does not change). The small file's figures are each host's
fixed costs (start-up, connect); the large file's, over them, are what the file's size costs.

  tests/bench/gcode_first_line.py MAHOST[,MAHOST...] SMALL.gcode LARGE.gcode [rounds=3] [stream_s=2] [boot_s=0]

Several mahost binaries (a build and the one before it), comma-separated, each run in turn
with printcore.

A large file: tests/bench/gcode_first_line.py --make LARGE.gcode [MB=200] writes rings of short
moves with ;LAYER: marks until the file has MB megabytes.
"""
import math
import os
import select
import signal
import statistics
import subprocess
import sys
import time
import tty


def make_large(path, megabytes):
    size, layer, e = 0, 0, 0.0
    with open(path, "w") as out:
        out.write("; rings for tests/bench/gcode_first_line.py\nG28\nG90\nM82\nG92 E0\n")
        while size < megabytes * 1_000_000:
            lines = [f";LAYER:{layer}\n;Z:{0.2 * (layer + 1):.2f}\nG1 Z{0.2 * (layer + 1):.2f} F600\n"]
            for ring in range(20):
                r = 20 + 0.4 * ring
                for i in range(400):
                    a = 2 * math.pi * i / 400
                    e += 0.0123
                    lines.append(f"G1 X{100 + r * math.cos(a):.3f} Y{100 + r * math.sin(a):.3f} E{e:.5f}\n")
            text = "".join(lines)
            out.write(text)
            size += len(text)
            layer += 1
        out.write("M84\n")


def first_command(path):
    with open(path) as f:
        for line in f:
            command = line.split(";")[0].strip()
            if command:
                return command
    raise SystemExit(f"{path}: no command")


def peak_kib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return -1


def cpu_s(pid):
    """CPU seconds (user and system) the process has used so far: load-independent, unlike
    the wall time on a shared machine."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except OSError:
        return None


def run(argv_of_port, gcode, stream_s, boot_s=0, limit_s=600):
    """(seconds to the file's first command or None, peak KiB, CPU seconds to the first command)"""
    master, slave = os.openpty()
    tty.setraw(slave)
    port = os.ttyname(slave)
    want = first_command(gcode)
    start = time.monotonic()
    host = subprocess.Popen(argv_of_port(port), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    first, pending, peak, cpu = None, b"", -1, None
    booted = boot_s <= 0
    while time.monotonic() - start < limit_s:
        if not booted and time.monotonic() - start >= boot_s:
            booted = True
            pending = b""
            os.write(master, b"start\necho: stand-in booted\n")
        if first is not None and time.monotonic() - first_at >= stream_s:
            break
        ready, _, _ = select.select([master], [], [], 0.05)
        peak = max(peak, peak_kib(host.pid))
        if host.poll() is not None:
            break
        if not ready:
            continue
        try:
            pending += os.read(master, 65536)
        except OSError:
            break
        *lines, pending = pending.split(b"\n")
        if not booted:
            continue  # a board in its bootloader: what it is sent is lost
        for raw in lines:
            text = raw.decode("ascii", "replace").strip()
            # N<n> <command>*<checksum>, or the command alone
            if text.startswith("N") and " " in text:
                text = text.split(" ", 1)[1]
            text = text.split("*")[0].strip()
            if first is None and text == want:
                first_at = time.monotonic()
                first = first_at - start
                cpu = cpu_s(host.pid)
            reply = b"ok\n"
            if text.startswith("M115"):
                reply = b"FIRMWARE_NAME:Marlin 2.1.2 (stand-in)\nok\n"
            os.write(master, reply)
    peak = max(peak, peak_kib(host.pid))
    host.send_signal(signal.SIGKILL)
    host.wait()
    os.close(master)
    os.close(slave)
    return first, peak, cpu


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "--make":
        make_large(sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 200)
        return 0
    if len(sys.argv) < 4:
        print(__doc__)
        return 2
    mahost, small, large = sys.argv[1:4]
    rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    stream_s = float(sys.argv[5]) if len(sys.argv) > 5 else 2
    boot_s = float(sys.argv[6]) if len(sys.argv) > 6 else 0
    binaries = mahost.split(",")
    hosts = {}
    for binary in binaries:
        name = "mahost" if len(binaries) == 1 else binary
        hosts[name] = (lambda b: lambda g: (lambda port: [b, "print", g, "--port", port, "--baud", "115200"]))(binary)
    hosts["printcore"] = lambda g: (lambda port: ["printcore", "-b", "115200", port, g])
    results = {(h, f): [] for h in hosts for f in (small, large)}
    for _ in range(rounds):
        for f in (small, large):
            for h, argv in hosts.items():
                results[(h, f)].append(run(argv(f), f, stream_s, boot_s))
    print(f"{rounds} rounds, alternated; medians; the small file {os.path.getsize(small)} bytes, the large "
          f"{os.path.getsize(large) / 1e6:.1f} MB; "
          + (f"a board that boots {boot_s:g} s" if boot_s > 0 else "a board without a banner"))
    for h in hosts:
        for f in (small, large):
            firsts = [r[0] for r in results[(h, f)] if r[0] is not None]
            peaks = [r[1] for r in results[(h, f)]]
            cpus = [r[2] for r in results[(h, f)] if r[2] is not None]
            cpu = f"{statistics.median(cpus):.2f} s" if cpus else "-"
            first = f"{statistics.median(firsts):.2f} s" if len(firsts) == rounds else \
                f"never in {rounds - len(firsts)} of {rounds} runs"
            print(f"  {h:<10} {os.path.basename(f):<16} first line {first:<12} (CPU {cpu:<8}) peak memory "
                  f"{statistics.median(peaks) / 1024:.0f} MiB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
