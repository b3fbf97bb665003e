#!/usr/bin/env bash
# Checks that invmap's layers depend one way, as the folders say: every
# #include of a project header ("folder/file.h") names a folder that the
# including folder may use (the table below), and every top-level folder
# with C++ sources has a row in the table. Prints each violation as
# "file:line: includes header (folder may use: ...)" and exits 1 when there
# is any. ctest runs it (label layers).
#
#   scripts/check_layers.sh [ROOT]    (default: the repository holding this script)
set -euo pipefail
root=$(cd "${1:-$(dirname "$0")/..}" && pwd)

# What each folder may include besides its own headers. "invmap" is the
# public API (include/invmap/); tests, benchmarks and fuzzers may use every
# library but not the command or the Python module.
libraries="common kernels pou engine implicit fields io implicit_io fem cad samples invmap"
declare -A may_use=(
  [include]="invmap"
  [common]=""
  [kernels]="common invmap"
  [pou]="common invmap"
  [engine]="common kernels pou invmap"
  [implicit]="common invmap"
  [fields]="common kernels engine invmap"
  [io]="common kernels invmap"
  [fem]="common kernels io invmap"
  [cad]="common kernels engine io invmap"
  [implicit_io]="common implicit io invmap"
  [samples]="invmap"
  [cli]="common io implicit_io fem cad samples invmap"
  [python]="common io implicit_io fem cad invmap"
  [examples]="invmap"
  [bench]="$libraries"
  [fuzz]="$libraries"
  [tests]="$libraries"
)

sources() { find "$@" -type f \( -name '*.h' -o -name '*.hpp' -o -name '*.cpp' -o -name '*.cc' \) -print0; }

violations=0
report() {
  echo "$1"
  violations=$((violations + 1))
}

# Every include path starts with one of these when it names a project header.
declare -A project_prefix=([invmap]=1)
for folder in "${!may_use[@]}"; do project_prefix[$folder]=1; done
for dir in "$root"/*/; do
  folder=$(basename "$dir")
  case $folder in build* | .*) continue ;; esac
  if [ -n "$(sources "$dir" | head -c 1)" ]; then
    project_prefix[$folder]=1
    [ -n "${may_use[$folder]+set}" ] || report "$folder/: no row in the layer table of scripts/check_layers.sh"
  fi
done

include_line='^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]([^">]+)[">]'
for folder in "${!may_use[@]}"; do
  [ -d "$root/$folder" ] || continue
  allowed=" $folder ${may_use[$folder]} "
  while IFS= read -r match; do
    file=${match%%:*}
    rest=${match#*:}
    number=${rest%%:*}
    [[ ${rest#*:} =~ $include_line ]] || continue
    header=${BASH_REMATCH[1]}
    prefix=${header%%/*}
    [ "$prefix" != "$header" ] || continue                # a header beside the file
    [ -n "${project_prefix[$prefix]+set}" ] || continue  # a system or third-party header
    if [ "$prefix" = include ]; then
      report "${file#"$root"/}:$number: includes $header (public headers are included as invmap/...)"
    elif [[ $allowed != *" $prefix "* ]]; then
      report "${file#"$root"/}:$number: includes $header ($folder/ may use: ${may_use[$folder]:-nothing})"
    fi
  done < <(grep -rnE --include='*.h' --include='*.hpp' --include='*.cpp' --include='*.cc' \
             '^[[:space:]]*#[[:space:]]*include' "$root/$folder" || true)
done

if [ $violations -gt 0 ]; then
  echo "$violations layer violation(s)"
  exit 1
fi
echo "layers: every include goes one way"
