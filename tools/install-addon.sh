#!/usr/bin/env bash
# Installs the add-on folder (addon/phos, with lib/libphos.so) into the
# user's Blender add-on folder, so that `blender --addons phos` finds it.
#
#   tools/install-addon.sh            install (replaces an earlier install)
#   tools/install-addon.sh --remove   uninstall
#
# BLENDER picks the Blender binary (default: blender). The destination is
# what that Blender reports as its user add-on folder, so BLENDER_USER_SCRIPTS
# is honoured.
#
# The add-on is copied, not symlinked: the installed copy is a snapshot that
# keeps working through `make clean`, a branch switch or a half-finished
# rebuild in the source tree. The new copy is staged next to the old one and
# moved into place by rename, so a running Blender keeps the library it has
# loaded.
set -euo pipefail
cd "$(dirname "$0")/.."
BLENDER=${BLENDER:-blender}

dest=$("$BLENDER" -b --factory-startup --python-expr \
  "import bpy; print('PHOS_ADDONS_DIR=' + bpy.utils.user_resource('SCRIPTS', path='addons'))" \
  2>/dev/null | sed -n 's/^PHOS_ADDONS_DIR=//p')
if [[ -z "$dest" ]]; then
  echo "install: could not ask $BLENDER for its user add-on folder" >&2
  exit 1
fi

if [[ "${1:-}" == "--remove" ]]; then
  rm -rf "$dest/phos"
  echo "install: removed $dest/phos"
  exit 0
fi

if [[ ! -f addon/phos/lib/libphos.so ]]; then
  echo "install: addon/phos/lib/libphos.so is missing: run 'make build' first" >&2
  exit 1
fi
if [[ ! -f addon/phos/__init__.py ]]; then
  echo "install: addon/phos/__init__.py is missing" >&2
  exit 1
fi

mkdir -p "$dest"
stage=$(mktemp -d "$dest/.phos-install.XXXXXX")
trap 'rm -rf "$stage"' EXIT
tar -C addon --exclude=__pycache__ --exclude='*.pyc' -cf - phos | tar -C "$stage" -xf -
if [[ -e "$dest/phos" || -L "$dest/phos" ]]; then
  mv "$dest/phos" "$stage/phos.old"
fi
mv "$stage/phos" "$dest/phos"
echo "install: installed the Phos add-on in $dest/phos"
echo "install: render with: $BLENDER -b --addons phos FILE.blend -E PHOS -f 1"
