#!/usr/bin/env bash
# Sets up an official Blender build as a Python module (`bpy` from PyPI) and
# a `blender` command for it, for `make test-blender-latest` and `make bench`.
#
#   tools/bpy-env.sh VERSION DIR     e.g. tools/bpy-env.sh 4.5.15 build/bpy/4.5.15
#
# DIR/venv     a virtual environment of this system's python3 with bpy==VERSION
#              and pytest (bpy brings numpy)
# DIR/blender  runs tools/bpy_blender.py with that Python: Blender's command
#              line (-b, --python, --addons, FILE.blend -E -o -F -f, --command
#              extension ...) for the module, so every script and target that
#              takes BLENDER=... runs against this release
#
# A bpy wheel is built for one Python (4.5 and 5.0: 3.11; 5.1 and later:
# 3.13), so VERSION must suit this system's python3: tools/bpy-versions.txt
# says where each release runs. The Debian packages the module needs
# (python3-venv and the X11 client libraries it links) are installed like
# every other dependency (tools/install-deps.sh --bpy). A ready DIR is
# reused: its bpy is checked, not reinstalled. If the package index cannot
# be reached, this stops with one line saying so and exit code 1.
set -euo pipefail
version=${1:?usage: tools/bpy-env.sh VERSION DIR}
dir=${2:?usage: tools/bpy-env.sh VERSION DIR}
repo=$(cd "$(dirname "$0")/.." && pwd -P)
mkdir -p "$dir"
dir=$(cd "$dir" && pwd -P)
venv=$dir/venv
python=/usr/bin/python3   # Debian's, whatever else is on PATH (pyenv, conda)

die() { echo "bpy-env: $*" >&2; exit 1; }

"$repo/tools/install-deps.sh" --bpy

ready() {
  [[ -x "$venv/bin/python" ]] &&
    "$venv/bin/python" -c "import sys, bpy, pytest
sys.exit(0 if bpy.app.version_string.split()[0] == '$version' else 1)" >/dev/null 2>&1
}

if ! ready; then
  echo "bpy-env: installing Blender $version (bpy from the Python package index, about 400 MB) into $venv"
  rm -rf "$venv"
  "$python" -m venv "$venv" || die "could not create a virtual environment with $python (python3-venv)"
  log=$dir/pip.log
  if ! "$venv/bin/python" -m pip install --disable-pip-version-check --no-input --retries 2 --timeout 60 \
       "bpy==$version" pytest >"$log" 2>&1; then
    tail -n 5 "$log" >&2
    if grep -qiE 'NewConnectionError|Max retries exceeded|Temporary failure in name resolution|Name or service not known|Network is unreachable|ConnectTimeout|ProxyError|Connection refused|SSLError' "$log"; then
      die "the Python package index cannot be reached, so bpy==$version cannot be installed; nothing was tested (log: $log)"
    fi
    die "pip could not install bpy==$version for $("$python" --version) (a bpy wheel serves one Python: see tools/bpy-versions.txt; log: $log)"
  fi
  ready || die "bpy==$version installed but 'import bpy' fails in $venv (log: $log)"
fi

# The module's own libraries must all resolve (the GPU denoiser plug-ins it
# loads on demand are not checked: they need GPU drivers, never used here).
module=$("$venv/bin/python" -c "import importlib.util, os
print(os.path.dirname(importlib.util.find_spec('bpy').origin))")
missing=$(ldd "$module"/__init__*.so | awk '/not found/ {print $1}' | sort -u | tr '\n' ' ')
[[ -z "$missing" ]] || die "the bpy module needs libraries this system lacks: $missing(add their Debian packages to tools/install-deps.sh --bpy)"

cat >"$dir/blender" <<SH
#!/bin/sh
# Blender $version as a Python module: written by tools/bpy-env.sh.
exec "$venv/bin/python" "$repo/tools/bpy_blender.py" "\$@"
SH
chmod +x "$dir/blender"
echo "bpy-env: $("$dir/blender" --version 2>/dev/null | head -n 1) ready: $dir/blender"
