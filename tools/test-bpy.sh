#!/usr/bin/env bash
# Runs the whole Blender test suite against the official Blender builds of
# tools/bpy-versions.txt (Blender as a Python module, `bpy` from PyPI), each
# with its own Cycles as the parity reference and the add-on installed as a
# user installs it: the 4.2+ extension zip, through Blender's own installer.
#
#   tools/test-bpy.sh [pytest args]           every release of tools/bpy-versions.txt,
#                                             each where its Python is (debian12: here;
#                                             debian13: the chroot of tools/test-blender4.sh)
#   tools/test-bpy.sh --prepare               only set up every release's environment
#                                             (downloads; no build, no test): .ci/run does
#                                             it while `make test` runs
#   tools/test-bpy.sh --here VERSION ADDON_DIR [pytest args]
#                                             one release on this system, with the add-on
#                                             folder ADDON_DIR (phos/ with lib/libphos.so)
#
# For each release: tools/bpy-env.sh sets it up in $PHOS_BPY_DIR/VERSION
# (default build/bpy/VERSION); tools/package.py zips the add-on; the suite
# runs with throw-away user folders (tests/blender/run_tests.py --extension);
# then tools/check-addon.sh --extension installs the zip with
# `blender --command extension install-file` and renders a .blend with
# `blender -b FILE -E PHOS -f 1`, both through tools/bpy_blender.py.
# Nothing is reported as passed unless every release ran and passed.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd -P)
versions_file=tools/bpy-versions.txt

say() { echo "test-bpy: $*"; }
die() { echo "test-bpy: $*" >&2; exit 1; }
elapsed() { local s=$(( $(date +%s) - $1 )); printf '%dm%02ds' $((s / 60)) $((s % 60)); }

# ------------------------------------------------------- one release, here
if [[ "${1:-}" == "--here" ]]; then
  version=${2:?usage: test-bpy.sh --here VERSION ADDON_DIR [pytest args]}
  addon=${3:?usage: test-bpy.sh --here VERSION ADDON_DIR [pytest args]}
  shift 3
  [[ $# -gt 0 ]] || set -- -q
  [[ -f "$addon/lib/libphos.so" ]] || die "$addon/lib/libphos.so is missing: build first"
  dir=${PHOS_BPY_DIR:-$repo/build/bpy}/$version
  t=$(date +%s)
  tools/bpy-env.sh "$version" "$dir"
  blender=$dir/blender
  rm -rf "$dir/dist" "$dir/stage" "$dir/user"
  mkdir -p "$dir/stage"
  cp -r "$addon" "$dir/stage/phos"
  python3 tools/package.py --addon "$dir/stage/phos" --dist "$dir/dist" >/dev/null
  zip=$(ls "$dir"/dist/phos-*.zip)
  # Every user folder of Blender in the build folder: the user's own
  # preferences and add-ons cannot change the outcome.
  export BLENDER_USER_RESOURCES=$dir/user BLENDER_USER_CONFIG=$dir/user/config \
         BLENDER_USER_SCRIPTS=$dir/user/scripts BLENDER_USER_EXTENSIONS=$dir/user/extensions \
         BLENDER_USER_DATAFILES=$dir/user/datafiles
  unset PHOS_LIBRARY PHOS_ADDON_MODULE
  rc=0
  "$blender" -b --factory-startup --python-exit-code 1 --python tests/blender/run_tests.py -- \
    --extension "$zip" "$@" || { rc=1; say "Blender $version: tests FAILED"; }
  say "Blender $version: tests $(elapsed "$t")"
  BLENDER=$blender tools/check-addon.sh --extension "$zip" || { rc=1; say "Blender $version: extension check FAILED"; }
  exit $rc
fi

# ----------------------------------------------- every release, where it runs
[[ -f "$versions_file" ]] || die "$versions_file is missing"
if [[ "${1:-}" == "--prepare" ]]; then
  while read -r series version where _; do
    case "$series" in ''|'#'*) continue ;; esac
    case "$where" in
      debian12) tools/bpy-env.sh "$version" "${PHOS_BPY_DIR:-$repo/build/bpy}/$version" </dev/null ;;
      debian13) PHOS_CHROOT_SUITE=trixie tools/test-blender4.sh --prepare "$version" </dev/null ;;
      *) die "$versions_file: unknown place '$where' for $version" ;;
    esac
  done <"$versions_file"
  exit 0
fi
t_start=$(date +%s)
rc=0
ran=()
while read -r series version where _; do
  case "$series" in ''|'#'*) continue ;; esac
  say "Blender $version ($series) in $where"
  case "$where" in
    debian12)
      tools/test-bpy.sh --here "$version" addon/phos "$@" || rc=1 ;;
    debian13)
      PHOS_CHROOT_SUITE=trixie tools/test-blender4.sh --bpy "$version" "$@" || rc=1 ;;
    *) die "$versions_file: unknown place '$where' for $version" ;;
  esac
  ran+=("$version")
done <"$versions_file"
[[ ${#ran[@]} -gt 0 ]] || die "$versions_file lists no release"
if [[ $rc -eq 0 ]]; then
  say "passed on Blender ${ran[*]} (official bpy builds; $(elapsed "$t_start"))"
else
  say "FAILED on at least one of Blender ${ran[*]} ($(elapsed "$t_start"))"
fi
exit $rc
