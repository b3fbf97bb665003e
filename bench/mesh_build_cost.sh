#!/bin/bash
# Index size, build and end-to-end cost of triangle meshes, two invmap
# builds and Embree in the same run (docs/benchmarks.md, "Before and after").
#
#   bench/mesh_build_cost.sh WORK_DIR BEFORE_INVMAP AFTER_INVMAP EMBREE_COST TRIANGLES...
#
# EMBREE_COST is build/release/bench/peers/invmap_embree_cost. For each mesh
# (`invmap generate trimesh --triangles N`, made in WORK_DIR if missing):
# bytes a triangle of the index (`invmap info`); the build, as `invert` of
# one point end to end (read, build, one query; Embree: its scene from the
# same file), CPU seconds pinned to one core and wall seconds on two; and
# `invert` of 10^6 near points (spread 0.001) on one core, CPU seconds and
# peak resident set. Prints a Markdown table.
set -euo pipefail
work=$1 before=$(realpath "$2") after=$(realpath "$3") embree=$(realpath "$4")
shift 4
mkdir -p "$work"
cd "$work"
measure() { /usr/bin/time -f "%e %U %S %M" "$@" 2>&1 >/dev/null | tail -1; }
echo "| tool | triangles | index B/tri | build, 1 core: CPU s | build, 2 cores: wall s | 10^6 near points, 1 core: CPU s | peak MB | peak B/tri |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for n in "$@"; do
  mesh=trimesh_$n.ply
  [ -f "$mesh" ] || "$after" generate trimesh --triangles "$n" -o "$mesh"
  cells=$(grep -a -m1 "element face" "$mesh" | awk '{print $3}')
  [ -f near_$n.npy ] || "$after" generate points -g "$mesh" --kind near --spread 0.001 -n 1000000 --seed 5 -o near_$n.npy
  [ -f one_$n.npy ] || "$after" generate points -g "$mesh" --kind near --spread 0.001 -n 1 --seed 5 -o one_$n.npy
  for tool in before after embree; do
    bin=${!tool}
    if [ $tool = embree ]; then
      index=-
      one=$(measure taskset -c 0 "$bin" "$mesh" one_$n.npy)
      two=$(measure taskset -c 0,1 "$bin" "$mesh" one_$n.npy)
      near=$(measure taskset -c 0 "$bin" "$mesh" near_$n.npy)
    else
      mib=$("$bin" info -g "$mesh" | awk '/^memory/{print $2}')
      index=$(python3 -c "print(round($mib * 2**20 / $cells))")
      one=$(measure taskset -c 0 "$bin" invert -q -g "$mesh" -p one_$n.npy -o out.npy --threads 1)
      two=$(measure taskset -c 0,1 "$bin" invert -q -g "$mesh" -p one_$n.npy -o out.npy --threads 2)
      near=$(measure taskset -c 0 "$bin" invert -q -g "$mesh" -p near_$n.npy -o out.npy --threads 1)
    fi
    python3 - "$tool" "$cells" "$index" "$one" "$two" "$near" <<'PY'
import sys
tool, cells, index, one, two, near = sys.argv[1:]
cells = int(cells)
one, two, near = ([float(x) for x in t.split()] for t in (one, two, near))
print(f"| {tool} | {cells} | {index} | {one[1] + one[2]:.2f} | {two[0]:.2f} | {near[1] + near[2]:.2f} | "
      f"{near[3] / 1024:.0f} | {near[3] * 1024 / cells:.0f} |", flush=True)
PY
  done
done
rm -f out.npy
