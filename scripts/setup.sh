#!/usr/bin/env bash
# invmap set-up on a fresh Debian 12 machine (run as root). Idempotent: a second
# run installs nothing and rebuilds only what changed.
#
#   scripts/setup.sh demo   install what is missing, build in Release, run the main job on a bundled example
#   scripts/setup.sh test   install what is missing, build (Release + Debug/ASan/UBSan), run every test
set -euo pipefail

mode=${1:-demo}
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc)

packages=(build-essential cmake ninja-build pkg-config clang libclang-rt-14-dev libeigen3-dev libtbb-dev
          libembree-dev libgtest-dev libgmock-dev libbenchmark-dev nlohmann-json3-dev libcli11-dev gmsh
          python3-dev pybind11-dev python3-numpy python3-pytest python3-dask python3-distributed
          libvtk9-dev libexodusii-dev libnetcdf-dev libgmsh-dev liblzf-dev pcl-tools
          libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev
          occt-misc libxsimd-dev)
# The distance benchmark's peers (bench/peers/distance_peers.cpp): FCL and OpenCascade's BRepExtrema.
packages+=(libfcl-dev libocct-modeling-algorithms-dev)

install_missing() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "== installing: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}

# configure_and_build DIR BUILD_TYPE [cmake -D args...] [--target TARGETS...]
configure_and_build() {
  local dir=$1 type=$2
  shift 2
  local defines=() targets=()
  while [ $# -gt 0 ]; do
    if [ "$1" = "--target" ]; then shift; targets=("$@"); break; fi
    defines+=("$1")
    shift
  done
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" "${defines[@]}" > "$dir.configure.log" 2>&1 \
    || { cat "$dir.configure.log"; exit 1; }
  if [ ${#targets[@]} -gt 0 ]; then
    cmake --build "$dir" -j "$jobs" --target "${targets[@]}"
  else
    cmake --build "$dir" -j "$jobs"
  fi
}

install_missing
mkdir -p "$root/build"
case "$mode" in
  demo)
    configure_and_build "$root/build/release" Release -DINVMAP_BUILD_TESTS=OFF -DINVMAP_BUILD_BENCH=OFF
    # The main job: a simulated scan of the bundled bracket checked against
    # its CAD model, signed (negative inside the part), coloured by deviation.
    invmap="$root/build/release/cli/invmap"
    demo="$root/build/demo"
    mkdir -p "$demo"
    part="$root/examples/data/bracket.step"
    [ -f "$demo/scan.ply" ] || "$invmap" generate scan -g "$part" -n 1000000 -o "$demo/scan.ply"
    "$invmap" info -g "$part"
    "$invmap" invert --signed --color --tolerance 0.05 -g "$part" -p "$demo/scan.ply" -o "$demo/deviation.ply"
    echo "deviation map: $demo/deviation.ply (points coloured blue inside to red outside; CloudCompare, MeshLab)"
    ;;
  test)
    configure_and_build "$root/build/release" Release -DINVMAP_BUILD_TESTS=ON -DINVMAP_BUILD_BENCH=ON
    # The kernel and implicit-grid tests again with AddressSanitizer,
    # UndefinedBehaviorSanitizer and internal asserts: a Debug build at -O1 (at
    # -O0 the brute-force reference alone takes most of an hour under the
    # sanitizers).
    configure_and_build "$root/build/asan" Debug "-DCMAKE_CXX_FLAGS_DEBUG=-g -O1" -DINVMAP_SANITIZE=ON \
      -DINVMAP_ASSERT=ON -DINVMAP_BUILD_TESTS=ON -DINVMAP_BUILD_BENCH=OFF -DINVMAP_BUILD_PYTHON=OFF \
      --target invmap_kernel_tests invmap_implicit_tests
    # The readers under libFuzzer (clang, ASan/UBSan), one target each, a
    # bounded time each.
    CC=clang CXX=clang++ configure_and_build "$root/build/fuzz" RelWithDebInfo -DINVMAP_BUILD_FUZZ=ON \
      -DINVMAP_SANITIZE=ON -DINVMAP_BUILD_TESTS=OFF -DINVMAP_BUILD_BENCH=OFF -DINVMAP_BUILD_PYTHON=OFF
    echo "== Release suite"
    ctest --test-dir "$root/build/release" -j "$jobs" --output-on-failure --timeout 900
    echo "== Debug + ASan/UBSan suite"
    ctest --test-dir "$root/build/asan" -j "$jobs" --output-on-failure --timeout 900 -L sanitize
    # Each target from the corpus of what fuzzing found before (fuzz/corpus)
    # into a scratch corpus of its own, as many at once as there are cores:
    # twelve targets of 10 s each take a minute on 2 cores.
    echo "== Fuzzing the readers (${INVMAP_FUZZ_SECONDS:-10} s each, $jobs at a time)"
    fuzz_one() {
      local target=$1 corpus="$root/build/fuzz/corpus/$1" leaks=1
      mkdir -p "$corpus"
      # VTK 9.1's XML reader leaks a few hundred bytes on some malformed
      # files (its own arrays, not invmap's): leaks are not checked there.
      [ "$target" = fuzz_fem ] && leaks=0
      ASAN_OPTIONS="detect_leaks=$leaks" "$root/build/fuzz/fuzz/$target" -max_total_time="${INVMAP_FUZZ_SECONDS:-10}" \
        -rss_limit_mb=2048 -timeout=10 -max_len=4096 -print_final_stats=1 "$corpus" "$root/fuzz/corpus/${target#fuzz_}" \
        > "$corpus.log" 2>&1
      local status=$?
      echo "$target: $(grep -E 'stat::number_of_executed_units' "$corpus.log" | tr -s ' ')"
      [ $status -eq 0 ] || { tail -n 40 "$corpus.log"; return 1; }
    }
    export -f fuzz_one
    export root
    xargs -P "$jobs" -I{} bash -c 'fuzz_one {}' < "$root/build/fuzz/fuzz_targets.txt"
    ;;
  *)
    echo "usage: scripts/setup.sh demo|test" >&2
    exit 2
    ;;
esac
