#!/usr/bin/python3
"""`mahost serve` under the load of serve_load_test.cpp, timed: 70 clients polling GET /api/job
at 10 Hz on kept-alive connections (from ten loopback addresses), with and without 60 clients
trickling a request's head a byte a second (from six more), while a dry-run print runs.

Usage: serve_load.py MAHOST [SECONDS=20] [ROUNDS=3]

Each round starts a server (`mahost serve --dry-run --time-scale 5`, a ring of 400 layers
printing), runs the pollers for SECONDS, and in the middle sends pause, resume and cancel from
127.0.0.1 on connections of their own; the rounds alternate between the two loads. Reports the
pollers' latency (median, 99th percentile, worst) and their error count, and the controls'
latency, for each load (the medians over the rounds), and the ratio of the p99 with the
trickling clients to the p99 without: what 60 slow clients cost the others.
"""
import json
import math
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

KEY = "serve-load-key-0123456789abcdef0"


def ring(layers, segments=60):
    g = ["G28", "G90", "M82", "G92 E0"]
    for layer in range(layers):
        z = 0.2 * (layer + 1)
        r = 20 + 5 * math.sin(layer * 0.1)
        g += [f";LAYER:{layer}", f";Z:{z:.3f}", "G92 E0", f"G1 Z{z:.3f} F600", f"G0 X{100 + r:.3f} Y100 F6000"]
        e = 0.0
        for i in range(1, segments + 1):
            a = 2 * math.pi * i / segments
            e += 2 * math.pi * r / segments * 0.0333
            g.append(f"G1 X{100 + r * math.cos(a):.3f} Y{100 + r * math.sin(a):.3f} E{e:.5f} F1800")
    return "\n".join(g + ["M84"]) + "\n"


def connect(port, source):
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind((source, 0))
    s.connect(("127.0.0.1", port))
    s.settimeout(60)
    return s


def read_response(s, pending):
    while b"\r\n\r\n" not in pending[0]:
        chunk = s.recv(65536)
        if not chunk:
            return None
        pending[0] += chunk
    head, rest = pending[0].split(b"\r\n\r\n", 1)
    length = 0
    for line in head.split(b"\r\n"):
        if line.lower().startswith(b"content-length:"):
            length = int(line.split(b":")[1])
    while len(rest) < length:
        chunk = s.recv(65536)
        if not chunk:
            return None
        rest += chunk
    pending[0] = rest[length:]
    return int(head[9:12])


def request(port, source, text):
    s = connect(port, source)
    start = time.monotonic()
    s.sendall(text)
    status = read_response(s, [b""])
    s.close()
    return status, time.monotonic() - start


def round_(mahost, seconds, slow):
    scratch = tempfile.mkdtemp()
    run = os.path.join(scratch, "run")
    os.makedirs(run, mode=0o700)
    env = dict(os.environ, MAHOST_API_KEY=KEY, XDG_RUNTIME_DIR=run, HOME=scratch)
    server = subprocess.Popen([mahost, "serve", "--dry-run", "--time-scale", "5", "--listen", "127.0.0.1:0",
                               "--files", os.path.join(scratch, "files")],
                              stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, env=env, text=True)
    port = int(server.stdout.readline().split()[2].rstrip("/").rsplit(":", 1)[1])
    path = os.path.join(scratch, "ring.gcode")
    with open(path, "w") as f:
        f.write(ring(400))
    subprocess.run(["curl", "-sf", "-H", f"X-Api-Key: {KEY}", "-F", f"file=@{path}", "-F", "print=true",
                    f"http://127.0.0.1:{port}/api/files/local"], check=True, capture_output=True)
    get = f"GET /api/job HTTP/1.1\r\nHost: x\r\nX-Api-Key: {KEY}\r\n\r\n".encode()
    done = threading.Event()
    latencies, errors = [], [0]
    lock = threading.Lock()

    def poller(source):
        while not done.is_set():
            s = connect(port, source)
            pending = [b""]
            while not done.is_set():
                start = time.monotonic()
                s.sendall(get)
                status = read_response(s, pending)
                with lock:
                    if status == 200:
                        latencies.append(time.monotonic() - start)
                    else:
                        errors[0] += 1
                if status != 200:
                    break
                time.sleep(0.1)
            s.close()

    def trickler(source):
        while not done.is_set():
            s = connect(port, source)
            try:
                for byte in get[:-2]:
                    if done.is_set():
                        break
                    s.send(bytes([byte]))
                    time.sleep(1)
            except OSError:
                pass
            s.close()

    threads = [threading.Thread(target=poller, args=(f"127.0.0.{2 + i % 10}",)) for i in range(70)]
    if slow:
        threads += [threading.Thread(target=trickler, args=(f"127.0.0.{20 + i % 6}",)) for i in range(60)]
    for t in threads:
        t.start()
    time.sleep(seconds / 2)
    controls = {}
    for name, body in [("pause", {"command": "pause", "action": "pause"}),
                       ("resume", {"command": "pause", "action": "resume"}), ("cancel", {"command": "cancel"})]:
        text = json.dumps(body)
        status, took = request(port, "127.0.0.1", (
            f"POST /api/job HTTP/1.1\r\nHost: x\r\nX-Api-Key: {KEY}\r\nContent-Type: application/json\r\n"
            f"Content-Length: {len(text)}\r\n\r\n{text}").encode())
        controls[name] = took if status == 204 else float("nan")
        time.sleep(1)
    time.sleep(seconds / 2)
    done.set()
    for t in threads:
        t.join()
    server.terminate()
    server.wait(60)
    shutil.rmtree(scratch)
    latencies.sort()
    return {"p50": latencies[len(latencies) // 2], "p99": latencies[int(len(latencies) * 0.99)],
            "worst": latencies[-1], "answers": len(latencies), "errors": errors[0], **controls}


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    mahost = os.path.abspath(sys.argv[1])
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 20
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    results = {False: [], True: []}
    for r in range(rounds):
        for slow in ([False, True] if r % 2 == 0 else [True, False]):
            results[slow].append(round_(mahost, seconds, slow))
    median = lambda slow, key: statistics.median(x[key] for x in results[slow])
    for slow in (False, True):
        print(f"{'70 pollers + 60 trickling' if slow else '70 pollers':26s} "
              f"p50 {1000 * median(slow, 'p50'):6.1f} ms  p99 {1000 * median(slow, 'p99'):6.1f} ms  "
              f"worst {1000 * median(slow, 'worst'):7.1f} ms  answers {median(slow, 'answers'):7.0f}  "
              f"errors {median(slow, 'errors'):.0f}  pause {1000 * median(slow, 'pause'):.1f} ms  "
              f"resume {1000 * median(slow, 'resume'):.1f} ms  cancel {1000 * median(slow, 'cancel'):.1f} ms")
    print(f"p99 with the trickling clients / without: {median(True, 'p99') / median(False, 'p99'):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
