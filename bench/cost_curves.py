#!/usr/bin/python3
"""Cost curves of triangle meshes: time and peak memory of `invmap invert`
against the mesh size and against the number of points, with Embree beside
(invmap_embree_cost: its scene built from the same file, every point queried
with rtcPointQuery). Both sides run end to end from the same files (read the
mesh, build, stream the points a chunk at a time), on the threads given, each
under GNU time for its wall time and peak resident memory.

    /usr/bin/python3 bench/cost_curves.py --build-dir build/release \\
        --work-dir build/cost_work --out bench/peers/results/cost

writes OUT.csv, OUT.md (the tables) and OUT_triangles.png, OUT_points.png
(the curves; needs python3-matplotlib). A configuration whose estimated
memory exceeds --max-memory-gb is skipped and listed as such.
"""
import argparse
import csv
import os
import re
import subprocess
import sys

INVMAP_BYTES_PER_TRIANGLE = 300  # peak resident set a triangle (about 175 on large meshes), with slack (docs/limitations.md#memory)


def parse_list(text):
    return [int(float(x)) for x in text.split(",") if x]


def run_timed(command, threads):
    """Runs `command` under GNU time (pinned to `threads` cores with taskset
    when fewer than all); returns (wall seconds, CPU seconds, peak MB,
    stdout). On a shared machine the wall time grows with the others' load;
    the CPU time (user + system) of a one-thread run does not."""
    if threads < os.cpu_count():
        command = ["taskset", "-c", ",".join(str(c) for c in range(threads))] + command
    result = subprocess.run(["/usr/bin/time", "-f", "TIME %e %U %S %M"] + command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(" ".join(command) + " failed:\n" + result.stderr[-2000:])
    match = re.search(r"TIME ([0-9.]+) ([0-9.]+) ([0-9.]+) ([0-9]+)", result.stderr)
    wall, user, system, peak = match.groups()
    return float(wall), float(user) + float(system), int(peak) / 1024.0, result.stdout


def ply_faces(path):
    with open(path, "rb") as f:
        for line in f:
            if line.startswith(b"element face"):
                return int(line.split()[2])
            if line.startswith(b"end_header"):
                break
    raise RuntimeError(path + ": no face element in the PLY header")


def ensure(path, command):
    if not os.path.exists(path):
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return path


def measure(args, triangles, points, rows):
    invmap = os.path.join(args.build_dir, "cli", "invmap")
    embree = os.path.join(args.build_dir, "bench", "peers", "invmap_embree_cost")
    mesh = ensure(os.path.join(args.work_dir, f"trimesh_{triangles}.ply"),
                  [invmap, "generate", "trimesh", "--triangles", str(triangles), "-o",
                   os.path.join(args.work_dir, f"trimesh_{triangles}.ply")])
    # The mesh generator rounds up to its subdivision levels: the real count,
    # from the PLY header (building the manifold to ask would take the memory
    # the estimate below is there to spare).
    cells = ply_faces(mesh)
    estimate = cells * INVMAP_BYTES_PER_TRIANGLE / 2**30
    row = {"triangles": cells, "points": points, "threads": args.threads}
    if estimate > args.max_memory_gb:
        rows.append(dict(row, tool="invmap", note=f"skipped: about {estimate:.1f} GB"))
        rows.append(dict(row, tool="Embree", note="skipped with invmap"))
        return
    name = os.path.join(args.work_dir, f"near_{triangles}_{points}_{args.spread}.npy")
    pts = ensure(name, [invmap, "generate", "points", "-g", mesh, "--kind", "near", "--spread", str(args.spread),
                        "-n", str(points), "--seed", "5", "-o", name])
    out = os.path.join(args.work_dir, "results.npy")
    wall, cpu, peak, _ = run_timed([invmap, "invert", "-q", "-g", mesh, "-p", pts, "-o", out,
                                    "--threads", str(args.threads)], args.threads)
    os.remove(out)
    rows.append(dict(row, tool="invmap", wall_s=wall, cpu_s=cpu, peak_mb=peak, note=""))
    wall, cpu, peak, stdout = run_timed([embree, mesh, pts], args.threads)
    fields = dict(kv.split("=") for kv in stdout.split())
    rows.append(dict(row, tool="Embree", wall_s=wall, cpu_s=cpu, peak_mb=peak, build_s=float(fields["build_s"]),
                     query_s=float(fields["query_s"]), note=""))
    if not args.keep_points:
        os.remove(pts)


def write_markdown(path, rows, command):
    with open(path, "w") as md:
        md.write("Command: `" + command + "`\n\n")
        md.write("Times are CPU seconds (user + system) of the whole command, end to end; peak memory is the "
                 "resident set's.\n\n")
        md.write("| triangles | points | threads | invmap s | Embree s | invmap / Embree time | "
                 "invmap MB | Embree MB | invmap / Embree memory |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
        pairs = {}
        for r in rows:
            pairs.setdefault((r["triangles"], r["points"], r["threads"]), {})[r["tool"]] = r
        for (tri, pts, thr), pair in sorted(pairs.items()):
            a, b = pair.get("invmap", {}), pair.get("Embree", {})
            if "cpu_s" not in a or "cpu_s" not in b:
                md.write(f"| {tri} | {pts} | {thr} | {a.get('note', '')} | | | | | |\n")
                continue
            md.write(f"| {tri} | {pts} | {thr} | {a['cpu_s']:.2f} | {b['cpu_s']:.2f} | "
                     f"{a['cpu_s'] / max(b['cpu_s'], 0.01):.2f} | {a['peak_mb']:.0f} | {b['peak_mb']:.0f} | "
                     f"{a['peak_mb'] / b['peak_mb']:.2f} |\n")


def plot(path, rows, x, fixed_label):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("cost_curves: python3-matplotlib is missing: no plots", file=sys.stderr)
        return
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for tool, style in (("invmap", "o-"), ("Embree", "s--")):
        series = sorted((r[x], r) for r in rows if r["tool"] == tool and "cpu_s" in r)
        if not series:
            continue
        left.plot([s[0] for s in series], [s[1]["cpu_s"] for s in series], style, label=tool)
        right.plot([s[0] for s in series], [s[1]["peak_mb"] for s in series], style, label=tool)
    for axis, label in ((left, "end-to-end CPU time (s)"), (right, "peak memory (MB)")):
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel(x)
        axis.set_ylabel(label)
        axis.grid(True, which="both", alpha=0.3)
        axis.legend()
    fig.suptitle(fixed_label)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", default="build/release")
    parser.add_argument("--work-dir", default="build/cost_work")
    parser.add_argument("--out", default="bench/peers/results/cost")
    parser.add_argument("--triangles", default="10000,100000,1000000,5000000,20000000",
                        help="mesh sizes of the first sweep (comma-separated)")
    parser.add_argument("--points-per-mesh", type=int, default=1000000, help="near points of the first sweep")
    parser.add_argument("--points", default="1000,10000,100000,1000000,10000000,100000000",
                        help="point counts of the second sweep")
    parser.add_argument("--mesh-for-points", type=int, default=1000000, help="triangles of the second sweep")
    parser.add_argument("--spread", type=float, default=0.001,
                        help="near points: largest offset relative to the mesh's size (a scan's noise)")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--max-memory-gb", type=float, default=16.0)
    parser.add_argument("--keep-points", action="store_true", help="keep the generated point files")
    args = parser.parse_args()
    os.makedirs(args.work_dir, exist_ok=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    rows = []
    for triangles in parse_list(args.triangles):
        measure(args, triangles, args.points_per_mesh, rows)
        print(rows[-2], rows[-1], sep="\n", flush=True)
    by_points = []
    for points in parse_list(args.points):
        measure(args, args.mesh_for_points, points, by_points)
        print(by_points[-2], by_points[-1], sep="\n", flush=True)
    keys = ["tool", "triangles", "points", "threads", "wall_s", "cpu_s", "peak_mb", "build_s", "query_s", "note"]
    with open(args.out + ".csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows + by_points)
    write_markdown(args.out + ".md", rows + by_points, " ".join(["/usr/bin/python3"] + sys.argv))
    plot(args.out + "_triangles.png", rows, "triangles", f"{args.points_per_mesh} near points (spread "
         f"{args.spread}), {args.threads} thread(s)")
    plot(args.out + "_points.png", by_points, "points", f"mesh of about {args.mesh_for_points} triangles, "
         f"{args.threads} thread(s)")


if __name__ == "__main__":
    main()
