#!/usr/bin/python3
"""An STL sliced through `mahost serve` against `mahost slice` with the same options.

Usage: serve_slice_time.py MAHOST MODEL.stl [N=3] [field=value ...]
  e.g. serve_slice_time.py build/mahost data/bunny.stl 3 units=m up=y height=50 support=buildplate

The fields are the slice command's (docs/serve-api.md), each given to `mahost slice` as
its option. Runs `mahost serve --dry-run` on a free loopback port; then N rounds, alternating
which goes first: the upload (multipart, with slice=true and the fields) until
/api/mahost/status says the slice is done, and `mahost slice` to a file. Reports the least and
the median wall time of each and their ratio, the same of the CPU time they took (the
server's user + system time over the round, the CLI process's: less moved by other work on a
shared machine than the wall time), and whether the two G-code files are the same but for the
model's path in the header.
"""
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

KEY = "slice-time-key-0123456789abcdef0"

# The slice command's fields as `mahost slice` options.
FLAGS = {"printer": "--printer", "material": "--material", "layer": "--layer", "contour": "--contour",
         "units": "--units", "up": "--up", "height": "--height", "scale": "--scale",
         "perimeters": "--perimeters", "infill": "--infill", "support": "--support", "brim": "--brim",
         "tolerance": "--tolerance", "maxLayers": "--max-layers", "maxTime": "--max-time", "orient": "--orient"}


def cli_args(fields):
    args = []
    for key, value in fields.items():
        if key == "raft":
            args.append("--raft" if value == "true" else "--no-raft")
        elif key == "adaptive":
            if value == "true":
                args.append("--adaptive")
        else:
            args += [FLAGS[key], value]
    return args


def upload(url, path, fields):
    boundary = "----mahost-slice-time"
    parts = []
    for key, value in dict(fields, slice="true").items():
        parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="{key}"\r\n\r\n{value}\r\n'.encode())
    with open(path, "rb") as f:
        body = f.read()
    parts.append(f'--{boundary}\r\nContent-Disposition: form-data; name="file"; filename="{os.path.basename(path)}"\r\n'
                 f'Content-Type: application/octet-stream\r\n\r\n'.encode() + body + b"\r\n")
    parts.append(f"--{boundary}--\r\n".encode())
    request = urllib.request.Request(url + "api/files/local", data=b"".join(parts), method="POST", headers={
        "X-Api-Key": KEY, "Content-Type": f"multipart/form-data; boundary={boundary}"})
    with urllib.request.urlopen(request) as reply:
        answer = json.load(reply)
    if answer.get("error") or answer.get("done"):
        raise SystemExit(f"not sliced: {answer}")


def status(url):
    request = urllib.request.Request(url + "api/mahost/status", headers={"X-Api-Key": KEY})
    with urllib.request.urlopen(request) as reply:
        return json.load(reply)["slicing"]


def cpu_seconds(pid):
    """User + system time of a process so far, s (/proc/PID/stat fields 14 and 15)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def children_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def without_model_line(path):
    with open(path) as f:
        return [line for line in f if not line.startswith("; model: ")]


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    mahost, model = sys.argv[1], os.path.abspath(sys.argv[2])
    rest = sys.argv[3:]
    rounds = int(rest.pop(0)) if rest and rest[0].isdigit() else 3
    fields = dict(item.split("=", 1) for item in rest)
    scratch = tempfile.mkdtemp(prefix="serve_slice_time_")
    runtime = os.path.join(scratch, "run")
    os.makedirs(runtime, mode=0o700)
    files = os.path.join(scratch, "files")
    env = dict(os.environ, MAHOST_API_KEY=KEY, XDG_RUNTIME_DIR=runtime, HOME=scratch,
               XDG_CONFIG_HOME=os.path.join(scratch, "config"))
    server = subprocess.Popen([mahost, "serve", "--dry-run", "--listen", "127.0.0.1:0", "--files", files],
                              stdout=subprocess.PIPE, stderr=open(os.path.join(scratch, "serve.log"), "w"),
                              env=env, text=True)
    try:
        url = server.stdout.readline().split()[2]
        served, direct, served_cpu, direct_cpu = [], [], [], []
        gcode = os.path.splitext(os.path.basename(model))[0] + ".gcode"
        out = os.path.join(scratch, "cli.gcode")
        for i in range(rounds):
            for which in (["api", "cli"] if i % 2 == 0 else ["cli", "api"]):
                start = time.monotonic()
                if which == "api":
                    cpu = cpu_seconds(server.pid)
                    upload(url, model, fields)
                    while True:
                        s = status(url)
                        if s and s["gcode"] == gcode and s["stage"] in ("done", "failed"):
                            break
                        time.sleep(0.02)
                    if s["stage"] != "done":
                        raise SystemExit(f"slicing failed: {s['error']}")
                    served.append(time.monotonic() - start)
                    served_cpu.append(cpu_seconds(server.pid) - cpu)
                else:
                    cpu = children_cpu_seconds()
                    subprocess.run([mahost, "slice", model, "-o", out] + cli_args(fields), check=True,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
                    direct.append(time.monotonic() - start)
                    direct_cpu.append(children_cpu_seconds() - cpu)
        same = without_model_line(os.path.join(files, gcode)) == without_model_line(out)
        print(f"fields: {fields or 'none (the profile defaults)'}; mahost slice {' '.join(cli_args(fields))}")
        print(f"serve (upload + slice): least {min(served):.2f} s, median {statistics.median(served):.2f} s of {rounds}")
        print(f"slice (CLI):            least {min(direct):.2f} s, median {statistics.median(direct):.2f} s of {rounds}")
        print(f"ratio serve/CLI: least {min(served) / min(direct):.3f}, median "
              f"{statistics.median(served) / statistics.median(direct):.3f}")
        print(f"CPU: serve least {min(served_cpu):.2f} s, median {statistics.median(served_cpu):.2f} s; "
              f"CLI least {min(direct_cpu):.2f} s, median {statistics.median(direct_cpu):.2f} s; ratio least "
              f"{min(served_cpu) / min(direct_cpu):.3f}, median {statistics.median(served_cpu) / statistics.median(direct_cpu):.3f}")
        print(f"G-code: {'the same' if same else 'DIFFERENT'} but for the model line")
        return 0 if same else 1
    finally:
        server.terminate()
        server.wait(30)


if __name__ == "__main__":
    sys.exit(main())
