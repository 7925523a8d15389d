#!/usr/bin/env bash
# Installs the Debian packages Phos needs to build, test, render and package.
# A fast no-op when everything is already installed.
#
#   tools/install-deps.sh            install what is missing
#   tools/install-deps.sh --check    only list what is missing (exit 1 if any)
#   tools/install-deps.sh --bench    also the packages of `make bench` (may be combined with --check)
#   tools/install-deps.sh --reliability  also valgrind and clang's libFuzzer (`make valgrind`, `make fuzz`)
#   tools/install-deps.sh --bpy      also what Blender as a Python module needs (tools/bpy-env.sh)
#   tools/install-deps.sh --chroot   also debootstrap, for the Debian 13 chroot (tools/test-blender4.sh)
#   tools/install-deps.sh --gui      also Xvfb, for the GUI test (`make test-gui`)
#   tools/install-deps.sh --farm     also Slurm, munge and Node.js, for the render-farm tests
set -euo pipefail

PACKAGES=(
  blender          # the host application (3.4 on Debian 12)
  libembree-dev    # ray-tracing kernels (Embree 3)
  cmake gcc make libc6-dev pkg-config
  python3-numpy    # Blender's Python on Debian is the system Python 3
  python3-pytest   # the Blender test suite runs pytest inside Blender
  zip
)

# Only for `make bench`: the kd-tree benchmark compares with nanoflann (C++),
# and the plots are drawn by Debian's Python with matplotlib.
BENCH_PACKAGES=(
  libnanoflann-dev # header-only kd-tree library
  g++
  python3-matplotlib
  python3-numpy
)

# Only for Blender as a Python module (`bpy` from PyPI, tools/bpy-env.sh):
# a virtual environment, and the X11 client libraries the module links
# although it never opens a window. A|B: either is enough (Debian 13
# renamed libxt6 to libxt6t64 in its 64-bit time_t transition; apt
# installs the virtual name A).
BPY_PACKAGES=(
  python3-venv
  libx11-6 libxext6 libxrender1 libxfixes3 libxi6 libxkbcommon0 "libxt6|libxt6t64" libsm6 libice6 libgl1
)

# Only for the Debian 13 chroot of `make test-blender4` (tools/test-blender4.sh):
# debootstrap, and Debian's archive keys that verify trixie's Release file.
CHROOT_PACKAGES=(
  debootstrap
  debian-archive-keyring
)

# Only for `make test-gui`: a virtual X server for Blender's GUI, drawn with
# Mesa's software OpenGL (libgl1-mesa-dri).
GUI_PACKAGES=(
  xvfb
  libgl1-mesa-dri
)

# Only for `make valgrind` and `make fuzz` (gcc's sanitizers come with gcc).
RELIABILITY_PACKAGES=(
  valgrind
  clang            # libFuzzer is clang's
  libclang-rt-dev  # its runtime libraries (libFuzzer, ASan, UBSan for clang)
)

# Only for the render-farm tests (tests/blender/test_farm.py, docs/farm.md):
# a real single-machine Slurm cluster (its daemons are started by the test,
# never as services), munge for its authentication, and Node.js for the
# Flamenco job type's unit test. Without them those tests are skipped.
FARM_PACKAGES=(
  slurmctld slurmd slurm-client
  munge
  nodejs
)

check=0
for arg in "$@"; do
  case "$arg" in
    --check) check=1 ;;
    --bench) PACKAGES+=("${BENCH_PACKAGES[@]}") ;;
    --reliability) PACKAGES+=("${RELIABILITY_PACKAGES[@]}") ;;
    --bpy) PACKAGES+=("${BPY_PACKAGES[@]}") ;;
    --chroot) PACKAGES+=("${CHROOT_PACKAGES[@]}") ;;
    --gui) PACKAGES+=("${GUI_PACKAGES[@]}") ;;
    --farm) PACKAGES+=("${FARM_PACKAGES[@]}") ;;
    *) echo "usage: $0 [--check] [--bench] [--reliability] [--bpy] [--chroot] [--gui] [--farm]" >&2; exit 2 ;;
  esac
done

installed() {
  [[ "$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null || true)" == "installed" ]]
}
missing=()
for entry in "${PACKAGES[@]}"; do
  found=0
  IFS='|' read -r -a alternatives <<<"$entry"
  for pkg in "${alternatives[@]}"; do
    if installed "$pkg"; then found=1; break; fi
  done
  [[ $found -eq 1 ]] || missing+=("${alternatives[0]}")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

if [[ $check -eq 1 ]]; then
  echo "missing packages: ${missing[*]}"
  exit 1
fi

install_cmd="apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
if [[ $(id -u) -eq 0 ]]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  SUDO=(sudo -n)
else
  echo "phos: these Debian packages are missing: ${missing[*]}" >&2
  echo "phos: installing them needs root. Run this once as root, then retry:" >&2
  echo "" >&2
  echo "    $install_cmd" >&2
  echo "" >&2
  exit 1
fi

echo "phos: installing missing packages: ${missing[*]}"
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
"${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y --no-install-recommends "${missing[@]}"
echo "phos: packages installed"
