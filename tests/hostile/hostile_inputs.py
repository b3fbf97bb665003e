"""Hostile inputs against the invmap command, each run under a memory limit
(prlimit --as) and a time limit (timeout): lying sizes, endless and sparse
files, huge fans and degrees, generators asked for billions, interrupted
runs, outputs over inputs. Every case checks the exit code, the message, and
that the directory holds afterwards exactly what it should (no output where
the run failed, no hidden temporary file ever).

    python3 tests/hostile/hostile_inputs.py path/to/invmap [case-name-substring]

ctest runs it (label hostile); it prints one line a case and exits 1 if any
fails. Needs prlimit and timeout (util-linux, coreutils).
"""

import json
import math
import os
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time

# Address space allowed to a run: well above what the command needs for
# these small files (its threads' stacks and allocator arenas included),
# far below what reading a lying size or an endless file would take.
MEMORY = 1_000_000_000
# A run taking longer than this hangs, as far as this suite is concerned.
SECONDS = 60
# How long a generator asked for billions runs before it is stopped: it
# must still be running then, within MEMORY, and leave nothing behind.
STREAM_SECONDS = 4


class Case:
    """One run: `args` (with {dir} for the scratch directory), the files
    `setup` makes, the exit code and a part of the message expected, and
    the files that must exist afterwards (beyond those of the setup)."""

    def __init__(self, name, args, code, message="", setup=None, creates=(), memory=MEMORY, seconds=SECONDS,
                 stop_after=None, unchanged=()):
        self.name, self.args, self.code, self.message = name, args, code, message
        self.setup, self.creates, self.memory, self.seconds = setup, set(creates), memory, seconds
        self.stop_after = stop_after  # run under `timeout` this short: it must still be running then
        self.unchanged = unchanged  # setup files the run must leave byte for byte


def write(path, data):
    with open(path, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)


def sparse(path, size):
    with open(path, "wb") as f:
        f.truncate(size)


def surface(d, name="s.json", spans=2):
    """A small bicubic surface, written by hand (not by invmap generate)."""
    n = spans + 3
    knots = [0.0] * 3 + [i / spans for i in range(spans + 1)] + [1.0] * 3
    points = [[i / (n - 1), j / (n - 1), 0.1 * math.sin(3 * i / (n - 1)) * math.cos(2 * j / (n - 1))]
              for j in range(n) for i in range(n)]
    write(os.path.join(d, name), json.dumps({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
        {"kind": "bspline", "degrees": [3, 3], "knots": [knots, knots], "counts": [n, n], "control_points": points}]}))


def points(d, name="p.xyz", count=20):
    write(os.path.join(d, name), "".join(f"{0.05 * i} {0.5} {0.01 * (i % 3)}\n" for i in range(count)))


def volume(d, name, n, degree):
    knots = [0.0] * (degree + 1) + [i / (n - degree) for i in range(1, n - degree)] + [1.0] * (degree + 1)
    grid = [[i / (n - 1) + 0.05 * math.sin(3 * j / (n - 1)), j / (n - 1), k / (n - 1) + 0.05 * math.sin(2 * i / (n - 1))]
            for k in range(n) for j in range(n) for i in range(n)]
    write(os.path.join(d, name), json.dumps({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
        {"kind": "bspline", "degrees": [degree] * 3, "knots": [knots] * 3, "counts": [n] * 3,
         "control_points": grid}]}))


def link(target, name):
    return lambda d: os.symlink(target, os.path.join(d, name))


def chain(*steps):
    return lambda d: [step(d) for step in steps]


def ply_points_header(count):
    return (f"ply\nformat binary_little_endian 1.0\nelement vertex {count}\n"
            "property float x\nproperty float y\nproperty float z\nend_header\n").encode() + bytes(24)


def npy_header(rows):
    header = "{'descr': '<f8', 'fortran_order': False, 'shape': (%d, 3), }" % rows
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode() + bytes(48)


def stl_lying_count():
    return b"binary".ljust(80, b"\0") + struct.pack("<I", 4_000_000_000) + bytes(50)


def huge_fan(d):
    write(os.path.join(d, "fan.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf" + " 1 2 3" * 1_000_000 + "\n")


def invert(geometry, pts="p.xyz", output="r.csv", *extra):
    return ["invert", "-g", "{dir}/" + geometry, "-p", "{dir}/" + pts, "-o", "{dir}/" + output, "-q", *extra]


def cases():
    return [
        # Lying sizes: headers that claim more than the file holds.
        Case("ply points claiming 4e9 vertices", invert("s.json", "lie.ply"), 3, "lie.ply",
             chain(surface, lambda d: write(os.path.join(d, "lie.ply"), ply_points_header(4_000_000_000)))),
        Case("npy claiming 1e12 rows", invert("s.json", "lie.npy"), 3, "lie.npy",
             chain(surface, lambda d: write(os.path.join(d, "lie.npy"), npy_header(10**12)))),
        Case("off claiming 1e12 vertices", ["info", "-g", "{dir}/lie.off"], 3, "more than the remaining",
             lambda d: write(os.path.join(d, "lie.off"), "OFF\n1000000000000 1000000000000 0\n0 0 0\n")),
        Case("binary stl claiming 4e9 triangles", ["info", "-g", "{dir}/lie.stl"], 3, "not an STL file",
             lambda d: write(os.path.join(d, "lie.stl"), stl_lying_count())),
        Case("gmsh claiming 1e12 nodes", ["info", "-g", "{dir}/lie.msh"], 3, "lie.msh",
             lambda d: write(os.path.join(d, "lie.msh"), "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n"
                                                         "1 1000000000000 1 1000000000000\n3 1 0 1000000000000\n1\n")),
        # Endless files: /dev/zero under every reader's name.
        *[Case(f"/dev/zero as {ext} geometry", ["info", "-g", "{dir}/zero" + ext], 3, "zero" + ext,
               link("/dev/zero", "zero" + ext)) for ext in (".json", ".stl", ".obj", ".off", ".ply", ".msh")],
        *[Case(f"/dev/zero as {ext} points", invert("s.json", "zero" + ext), 3, "zero" + ext,
               chain(surface, link("/dev/zero", "zero" + ext))) for ext in (".xyz", ".csv", ".ply", ".npy")],
        *[Case(f"/dev/zero as grid {what}", ["grid", *args, "--box", "0,0,0,1,1,1", "-o", "{dir}/grid"], 3, "zero",
               chain(link("/dev/zero", "zero.json"), link("/dev/zero", "zero.msh"),
                     lambda d: write(os.path.join(d, "f.json"), '[{"type": "sphere", "center": [0.5, 0.5, 0.5], '
                                                                 '"radius": 0.3}]')))
          for what, args in (("functions", ["-f", "{dir}/zero.json"]),
                             ("tree", ["-f", "{dir}/f.json", "--mode", "csg", "--tree", "{dir}/zero.json"]))],
        Case("/dev/zero as initial grid", ["grid", "-f", "{dir}/f.json", "--grid", "{dir}/zero.msh", "-o", "{dir}/grid"],
             3, "zero.msh", chain(link("/dev/zero", "zero.msh"),
                                  lambda d: write(os.path.join(d, "f.json"), '[{"type": "sphere", "center": '
                                                                              '[0.5, 0.5, 0.5], "radius": 0.3}]'))),
        # Sparse files: gigabytes of zeros that cost no disk.
        *[Case(f"/dev/zero as {ext} geometry", ["info", "-g", "{dir}/zero" + ext], 3, "not a regular file",
               link("/dev/zero", "zero" + ext)) for ext in (".vtu", ".exo", ".e")],
        *[Case(f"2 GB sparse {ext}", ["info", "-g", "{dir}/big" + ext], 3, "big" + ext,
               lambda d, ext=ext: sparse(os.path.join(d, "big" + ext), 2 << 30)) for ext in (".vtu", ".exo", ".bext")],
        Case("6 GB sparse stl", ["info", "-g", "{dir}/big.stl"], 3, "this file has 6442450944",
             lambda d: sparse(os.path.join(d, "big.stl"), 6 << 30)),
        *[Case(f"2 GB sparse {ext}", ["info", "-g", "{dir}/big" + ext], 3, "big" + ext,
               lambda d, ext=ext: sparse(os.path.join(d, "big" + ext), 2 << 30)) for ext in (".json", ".obj", ".off")],
        Case("2 GB sparse points", invert("s.json", "big.xyz"), 3, "big.xyz",
             chain(surface, lambda d: sparse(os.path.join(d, "big.xyz"), 2 << 30))),
        # Huge fans and degrees.
        Case("an obj face of 3 million indices", ["info", "-g", "{dir}/fan.obj"], 0, "cells       1\n", huge_fan),
        Case("degree 9", ["info", "-g", "{dir}/deg9.json"], 3, "expected 1 to 8",
             lambda d: volume(d, "deg9.json", 10, 9)),
        Case("degree-8 volume of 20^3 control points", ["info", "-g", "{dir}/deg8.json"], 0, "hex 8x8x8            1728",
             lambda d: volume(d, "deg8.json", 20, 8), memory=2_000_000_000),
        # Generators asked for billions stream: still running (not out of
        # memory) when stopped, and their temporary file removed.
        Case("generate points --count 2e9", ["generate", "points", "-g", "{dir}/s.json", "--count", "2000000000",
                                              "-o", "{dir}/many.npy"], 124, "", surface, stop_after=STREAM_SECONDS),
        Case("generate trimesh --triangles 2e8", ["generate", "trimesh", "--triangles", "200000000",
                                                   "-o", "{dir}/many.ply"], 124, "", stop_after=STREAM_SECONDS),
        Case("generate tets --resolution 200", ["generate", "tets", "--resolution", "200", "-o", "{dir}/many.msh"],
             124, "", stop_after=STREAM_SECONDS),
        # Outputs over inputs, by any path.
        Case("output over the points", invert("s.json", "p.xyz", "p.xyz"), 2, "would destroy the input",
             chain(surface, points), unchanged=("p.xyz",)),
        Case("output over the geometry", invert("s.json", "p.xyz", "s.json"), 2, "would destroy the input",
             chain(surface, points), unchanged=("s.json",)),
        Case("output through a link to the points", invert("s.json", "p.xyz", "link.xyz"), 2, "would destroy the input",
             chain(surface, points, link("p.xyz", "link.xyz")), unchanged=("p.xyz",)),
        Case("trim onto its own input", ["trim", "-g", "{dir}/s.json", "-p", "{dir}/p.xyz", "-o", "{dir}/p.xyz",
                                         "--max-distance", "1", "-q"], 2, "would destroy the input",
             chain(surface, points), unchanged=("p.xyz",)),
        # Usage mistakes cost nothing: refused before the geometry is read.
        Case("unknown output extension before an endless geometry", invert("zero.json", "p.xyz", "r.xyzq"), 2,
             "unknown result file extension", chain(points, link("/dev/zero", "zero.json"))),
        Case("unknown command", ["frobnicate"], 2, "unknown command 'frobnicate'"),
        # More threads than cores: no raw library warning.
        Case("--threads 64", invert("s.json", "p.xyz", "r.csv", "--threads", "64"), 0, "", chain(surface, points),
             creates=("r.csv",)),
    ]


def interrupted_cases():
    """(name, signal): a large inversion stopped by a signal once its
    temporary output exists."""
    return [("SIGINT during invert", signal.SIGINT), ("SIGTERM during invert", signal.SIGTERM),
            ("SIGHUP during invert", signal.SIGHUP)]


def limited(invmap, case_args, memory, seconds, signal_name="KILL"):
    return ["timeout", "-s", signal_name, str(seconds), "prlimit", f"--as={memory}", invmap, *case_args]


def run_case(invmap, case, root):
    d = tempfile.mkdtemp(prefix="case-", dir=root)
    try:
        if case.setup:
            case.setup(d)
        before = set(os.listdir(d))
        kept = {name: open(os.path.join(d, name), "rb").read() for name in case.unchanged}
        args = [a.replace("{dir}", d) for a in case.args]
        if case.stop_after:
            # TERM, as a user's kill would: the run must clean up after itself.
            command = limited(invmap, args, case.memory, case.stop_after, "TERM")
        else:
            command = limited(invmap, args, case.memory, case.seconds)
        start = time.monotonic()
        done = subprocess.run(command, capture_output=True, text=True, errors="replace")
        seconds = time.monotonic() - start
        problems = []
        if done.returncode != case.code:
            problems.append(f"exit {done.returncode}, expected {case.code}")
        message = done.stderr + done.stdout
        if case.message and case.message not in message:
            problems.append(f"message lacks {case.message!r}")
        if "TBB Warning" in message or "Segmentation" in message:
            problems.append("a raw library message or a crash")
        if case.code in (2, 3, 4) and not message.startswith("invmap"):
            problems.append("the message does not come from invmap")
        after = set(os.listdir(d))
        left = after - before - case.creates
        if left:
            problems.append(f"left behind: {sorted(left)}")
        missing = case.creates - after
        if missing:
            problems.append(f"missing output: {sorted(missing)}")
        for name, data in kept.items():
            if open(os.path.join(d, name), "rb").read() != data:
                problems.append(f"{name} was changed")
        return problems, seconds, message.strip().splitlines()[:1]
    finally:
        shutil.rmtree(d, ignore_errors=True)


def run_interrupted(invmap, signo, root):
    d = tempfile.mkdtemp(prefix="signal-", dir=root)
    try:
        surface(d, spans=16)
        # Several chunks of 2^18 points, so the run takes a while.
        rows = 1_100_000
        with open(os.path.join(d, "p.npy"), "wb") as f:
            header = "{'descr': '<f8', 'fortran_order': False, 'shape': (%d, 3), }" % rows
            header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
            f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
            for block in range(0, rows, 100_000):
                n = min(100_000, rows - block)
                f.write(struct.pack(f"<{3 * n}d", *[(0.37 * (i % 97)) % 1.0 for i in range(3 * n)]))
        before = set(os.listdir(d))
        # prlimit execs the command, so the signal reaches invmap itself
        # (timeout would stand between them); the time limit is the wait's.
        process = subprocess.Popen(["prlimit", f"--as={MEMORY}", invmap, "invert", "-g", f"{d}/s.json", "-p",
                                    f"{d}/p.npy", "-o", f"{d}/r.csv", "--threads", "1", "-q"],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        # Until the hidden temporary output appears (or the run ends).
        deadline = time.monotonic() + SECONDS
        while process.poll() is None and time.monotonic() < deadline:
            if any(name.startswith(".") for name in os.listdir(d)):
                break
            time.sleep(0.005)
        problems = []
        if process.poll() is not None:
            problems.append("the run ended before it could be interrupted")
        process.send_signal(signo)
        code = process.wait(timeout=SECONDS)
        if code != -signo:
            problems.append(f"status {code}, expected to end by signal {signo} (the shell shows {128 + signo})")
        left = set(os.listdir(d)) - before
        if left:
            problems.append(f"left behind: {sorted(left)}")
        return problems
    finally:
        shutil.rmtree(d, ignore_errors=True)


def main():
    invmap = os.path.abspath(sys.argv[1])
    only = sys.argv[2] if len(sys.argv) > 2 else ""
    failed = 0
    with tempfile.TemporaryDirectory(prefix="invmap-hostile-") as root:
        for case in cases():
            if only not in case.name:
                continue
            problems, seconds, first_line = run_case(invmap, case, root)
            failed += bool(problems)
            print(f"{'FAIL' if problems else 'ok  '} {case.name} ({seconds:.1f} s) {first_line[0] if first_line else ''}")
            for problem in problems:
                print(f"     {problem}")
        for name, signo in interrupted_cases():
            if only not in name:
                continue
            problems = run_interrupted(invmap, signo, root)
            failed += bool(problems)
            print(f"{'FAIL' if problems else 'ok  '} {name}")
            for problem in problems:
                print(f"     {problem}")
    print(f"{failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
