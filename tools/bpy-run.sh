#!/usr/bin/env bash
# Runs a Blender command line under an official build of tools/bpy-versions.txt
# (Blender as a Python module, through tools/bpy_blender.py), where that
# release's Python is: here, or in the Debian 13 chroot of tools/test-blender4.sh.
#
#   tools/bpy-run.sh --newest                  print the newest release's version
#   tools/bpy-run.sh VERSION OUT -- ARGS...    run `blender ARGS...` under VERSION
#
# The command runs in the checkout (read-only in the chroot) with the add-on
# from the source tree and the library built for that system. Two words in
# ARGS are replaced by folders the run can write to: {out}, which ends up
# as the host folder OUT (in the chroot it is the build folder's bpy-out/,
# copied to OUT afterwards), and {cache}, a folder kept from run to run for
# that release (references of the benchmark).
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd -P)
versions_file=tools/bpy-versions.txt
die() { echo "bpy-run: $*" >&2; exit 1; }

releases() { awk '!/^#/ && NF >= 3 {print $2, $3}' "$versions_file"; }
if [[ "${1:-}" == "--newest" ]]; then
  releases | tail -n 1 | cut -d' ' -f1
  exit 0
fi
version=${1:?usage: tools/bpy-run.sh VERSION OUT -- ARGS...}
out=${2:?usage: tools/bpy-run.sh VERSION OUT -- ARGS...}
[[ "${3:-}" == "--" ]] || die "usage: tools/bpy-run.sh VERSION OUT -- ARGS..."
shift 3
where=$(releases | awk -v v="$version" '$1 == v {print $2}')
[[ -n "$where" ]] || die "$version is not in $versions_file"
mkdir -p "$out"
out=$(cd "$out" && pwd -P)

substitute() {   # substitute OUT_DIR CACHE_DIR ARGS...
  local o=$1 c=$2 a
  shift 2
  for a in "$@"; do
    a=${a//\{out\}/$o}
    printf '%s\0' "${a//\{cache\}/$c}"
  done
}

case "$where" in
  debian12)
    make build >/dev/null
    dir=${PHOS_BPY_DIR:-$repo/build/bpy}/$version
    tools/bpy-env.sh "$version" "$dir" >&2
    cache=$repo/build/bpy/$version/cache
    mkdir -p "$cache"
    mapfile -d '' args < <(substitute "$out" "$cache" "$@")
    exec "$dir/blender" "${args[@]}" ;;
  debian13)
    build=${PHOS_TRIXIE_BUILD_DIR:-$repo/build-trixie}
    rm -rf "$build/bpy-out"
    mkdir -p "$build/bpy-out" "$build/bpy/$version/cache"
    mapfile -d '' args < <(substitute /phos-build/bpy-out "/phos-build/bpy/$version/cache" "$@")
    rc=0
    PHOS_CHROOT_SUITE=trixie tools/test-blender4.sh --bpy-run "$version" "${args[@]}" || rc=$?
    cp -r "$build/bpy-out/." "$out/" 2>/dev/null || true
    exit $rc ;;
  *) die "$versions_file: unknown place '$where' for $version" ;;
esac
