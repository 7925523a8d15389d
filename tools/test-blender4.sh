#!/usr/bin/env bash
# Builds Phos against Embree 4 and runs the C tests and the Blender test suite
# under Blender 4.3, inside a Debian 13 (trixie) chroot. Needs root. With
# PHOS_CHROOT_SUITE=sid, the same in a Debian unstable chroot, whose Blender
# (5.2) is the newest with a window that Debian packages: `make
# test-blender5` runs its GUI tests there (--gui).
#
#   tools/test-blender4.sh [pytest args]   build, ctest, Blender tests (default args: -q),
#                                          the GUI tests (tools/test-gui.sh), then the
#                                          extension check (below)
#   tools/test-blender4.sh --gui           build, the GUI tests, the extension check
#                                          (--bpy and --bpy-run below need trixie: sid's
#                                          chroot has no Python venv nor bpy's X libraries)
#   tools/test-blender4.sh --bpy VERSION [pytest args]
#                                          build, then the Blender tests against the official
#                                          Blender VERSION as a Python module (bpy, Python 3.13)
#                                          in the chroot: tools/test-bpy.sh --here (make
#                                          test-blender-latest runs this for 5.1 and later)
#   tools/test-blender4.sh --bpy-run VERSION ARGS...
#                                          build, then `blender ARGS...` under the official
#                                          Blender VERSION (bpy) in the chroot, in /phos-src
#                                          with this build's library (tools/bpy-run.sh)
#   tools/test-blender4.sh --prepare [VERSION...]
#                                          only make the chroot ready (and the official
#                                          Blender VERSION's environment in its build folder,
#                                          tools/bpy-env.sh): downloads, no build, no test
#   tools/test-blender4.sh --shell         interactive shell in the chroot, same mounts
#   tools/test-blender4.sh --remove        delete the chroot
#
# The chroot is made once with `debootstrap --variant=minbase SUITE` from the
# Debian mirror in the host's apt sources, then reused; later runs only check
# that its packages are installed. Every mount (proc, sys, dev, tmp, the
# checkout read-only at /phos-src, the build folder at /phos-build) is made in
# a private mount and PID namespace (`unshare`), so nothing stays mounted when
# the run ends, however it ends, and deleting the chroot cannot reach the
# checkout. Nothing in the checkout is written except the build folder.
#
# After the tests, the Blender 4.2+ extension is checked as a user installs
# it: tools/package.py builds the zip (phos/ with blender_manifest.toml and
# the Embree-4 lib/libphos.so of this build) into the build folder's dist/,
# and tools/check-addon.sh --extension validates it with Blender, installs it
# with `blender --command extension install-file -r user_default -e` into
# throw-away user folders and renders a tiny scene with engine PHOS headless
# from there (PHOS_LIBRARY unset: the extension's own library), failing on a
# missing or black image.
#
# Environment:
#   PHOS_CHROOT_SUITE      trixie (default: Blender 4.3) or sid (Blender 5.2)
#   PHOS_CHROOT_DIR        the chroot (default /var/tmp/phos-SUITE-chroot)
#   PHOS_CHROOT_BUILD_DIR  build folder (default build-SUITE in the checkout; for trixie
#                          also PHOS_TRIXIE_BUILD_DIR, its older name); the
#                          Embree-4 libphos.so goes to its lib/, never to addon/phos/lib
#   PHOS_DEBIAN_MIRROR     Debian mirror URI (default: from /etc/apt/sources*)
#   JOBS                   parallel build/ctest jobs (default: nproc)
set -euo pipefail

SUITE=${PHOS_CHROOT_SUITE:-trixie}
case "$SUITE" in
  trixie)
    SUITE_NAME="Debian 13"
    PACKAGES=(
      blender          # 4.3 in trixie
      libembree-dev    # Embree 4
      cmake gcc g++ libc6-dev make pkg-config zip
      python3-numpy python3-pytest
      # bpy (--bpy): tools/install-deps.sh --bpy's list, so that it finds them all,
      # with trixie's names (libxt6 is libxt6t64 there: named as libxt6, it never
      # reads as installed, and every run would call apt again)
      python3-venv
      libx11-6 libxext6 libxrender1 libxfixes3 libxi6 libxkbcommon0 libxt6t64 libsm6 libice6 libgl1
      # the GUI tests (tools/test-gui.sh): Blender 4.3's window on Xvfb, Mesa's software OpenGL
      xvfb xauth libgl1-mesa-dri
    ) ;;
  sid)
    # Debian unstable: Blender 5.2 with its window, which the official 5.x
    # builds here (bpy modules) lack; Embree 4.4. Testing (forky) has no
    # Blender at the time of writing.
    SUITE_NAME="Debian unstable"
    PACKAGES=(
      blender libembree-dev
      cmake gcc g++ libc6-dev make pkg-config zip
      python3-numpy python3-pytest
      # Blender's extension manager imports cattrs and requests, which the package does not
      # pull in (without it, registering the extensions add-on fails)
      python3-cattr python3-requests
      xvfb xauth libgl1-mesa-dri
    ) ;;
  *) echo "test-blender4: PHOS_CHROOT_SUITE=$SUITE: trixie or sid" >&2; exit 1 ;;
esac
STAMP=var/lib/phos-chroot/ready   # inside the chroot: written once every package is in

say() { echo "test-blender4: $*"; }
die() { echo "test-blender4: $*" >&2; exit 1; }
elapsed() { local s=$(( $(date +%s) - $1 )); printf '%dm%02ds' $((s / 60)) $((s % 60)); }

# ------------------------------------------------ inside the private namespaces
# `unshare --mount --pid --fork` runs this script again with --in-namespace; it
# is PID 1 there. When it exits, the kernel ends every process of the PID
# namespace and with them the mount namespace: no mount survives the run.
if [[ "${1:-}" == "--in-namespace" ]]; then
  root=$2 src=$3 build=$4; shift 4
  trap 'exit 130' INT TERM HUP   # PID 1 ignores signals it has no handler for
  mount --make-rprivate /
  mount -t proc -o nosuid,nodev,noexec proc "$root/proc"
  mount -t sysfs -o ro,nosuid,nodev,noexec sysfs "$root/sys" 2>/dev/null \
    || mount --rbind -o ro /sys "$root/sys" 2>/dev/null || true
  mount -t tmpfs -o mode=755,nosuid dev "$root/dev"
  for n in null zero full random urandom tty; do
    touch "$root/dev/$n" && mount --bind "/dev/$n" "$root/dev/$n"
  done
  mkdir -p "$root/dev/pts" "$root/dev/shm"
  mount --bind /dev/pts "$root/dev/pts" 2>/dev/null || true
  mount -t tmpfs -o mode=1777,nosuid,nodev shm "$root/dev/shm"
  ln -s /proc/self/fd "$root/dev/fd"
  ln -s /proc/self/fd/0 "$root/dev/stdin"
  ln -s /proc/self/fd/1 "$root/dev/stdout"
  ln -s /proc/self/fd/2 "$root/dev/stderr"
  mount -t tmpfs -o mode=1777,nosuid,nodev tmp "$root/tmp"
  # Blender reads the mount table through /etc/mtab, which minbase lacks.
  [[ -e "$root/etc/mtab" || -L "$root/etc/mtab" ]] || ln -s ../proc/self/mounts "$root/etc/mtab"
  for f in resolv.conf hosts; do   # name resolution for apt, read-only
    if [[ -L "$root/etc/$f" ]]; then rm -f "$root/etc/$f"; fi   # never follow a link out
    touch "$root/etc/$f" && mount --bind -o ro "/etc/$f" "$root/etc/$f"
  done
  # The host's TLS trust and pip configuration, read-only, so that pip in
  # the chroot (bpy for --bpy) reaches the package index the way the host
  # does, through a proxy's own certificate authority included. Only for
  # runs with a build folder, never while apt installs packages: the
  # post-installation script of ca-certificates replaces
  # /etc/ssl/certs/ca-certificates.crt, which a bind mount pins (EBUSY).
  declare -A mounted=()   # SSL_CERT_FILE and REQUESTS_CA_BUNDLE often name one file
  tls_files=()
  if [[ -n "$build" ]]; then
    tls_files=(/etc/pip.conf "${PIP_CERT:-}" "${SSL_CERT_FILE:-}" "${REQUESTS_CA_BUNDLE:-}")
  fi
  for f in "${tls_files[@]}"; do
    [[ -n "$f" && "$f" == /* && -f "$f" && -z "${mounted[$f]:-}" ]] || continue
    mounted[$f]=1
    target=$root$f
    [[ -L "$target" ]] && rm -f "$target"
    mkdir -p "$(dirname "$target")" && touch "$target" && mount --bind -o ro "$f" "$target"
  done
  if [[ -n "$src" ]]; then
    mkdir -p "$root/phos-src"
    mount --bind "$src" "$root/phos-src"
    mount -o remount,bind,ro "$root/phos-src"
  fi
  if [[ -n "$build" ]]; then
    mkdir -p "$root/phos-build"
    mount --bind "$build" "$root/phos-build"
  fi
  envs=(HOME=/root LANG=C.UTF-8 TMPDIR=/tmp DEBIAN_FRONTEND=noninteractive
        PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin)
  for v in TERM JOBS http_proxy https_proxy no_proxy HTTP_PROXY HTTPS_PROXY NO_PROXY \
           PIP_CERT PIP_INDEX_URL PIP_EXTRA_INDEX_URL PIP_TRUSTED_HOST PIP_DEFAULT_TIMEOUT \
           SSL_CERT_FILE REQUESTS_CA_BUNDLE; do
    [[ -n "${!v:-}" ]] && envs+=("$v=${!v}")
  done
  rc=0
  chroot "$root" /usr/bin/env -i "${envs[@]}" "$@" || rc=$?
  exit "$rc"
fi

# ------------------------------------------------------------------ outside
cd "$(dirname "$0")/.."
repo=$(pwd -P)
chroot_dir=${PHOS_CHROOT_DIR:-/var/tmp/phos-$SUITE-chroot}
[[ "$chroot_dir" == /* ]] || chroot_dir="$repo/$chroot_dir"
chroot_dir=${chroot_dir%/}
build_dir=build-$SUITE
[[ "$SUITE" != trixie ]] || build_dir=${PHOS_TRIXIE_BUILD_DIR:-$build_dir}
build_dir=${PHOS_CHROOT_BUILD_DIR:-$build_dir}
[[ "$build_dir" == /* ]] || build_dir="$repo/$build_dir"
export JOBS=${JOBS:-$(nproc 2>/dev/null || echo 2)}
t_start=$(date +%s)

if [[ $(id -u) -ne 0 ]]; then
  die "needs root: debootstrap, chroot and mounts (even private ones) need it.
test-blender4: run it as root, e.g.  sudo make test-blender4"
fi
case "$chroot_dir" in
  ''|/|/var|/var/tmp|/tmp|/usr|/home|/root) die "PHOS_CHROOT_DIR=$chroot_dir is not a dedicated folder" ;;
esac
case "$chroot_dir/" in
  "$repo"/*) die "PHOS_CHROOT_DIR must be outside the checkout ($repo)" ;;
esac
case "$repo/" in
  "$chroot_dir"/*) die "the checkout must not be inside PHOS_CHROOT_DIR ($chroot_dir)" ;;
esac
for tool in unshare chroot flock findmnt; do
  command -v "$tool" >/dev/null || die "$tool is missing (util-linux / coreutils)"
done

# Fails if anything is mounted at or below the chroot in this (the host's)
# mount namespace: a run never leaves a mount there, so this is a leftover
# of something else and rm -rf or reuse would be unsafe.
check_no_mounts() {
  local m
  m=$(findmnt -rn -o TARGET | awk -v d="$1" '$0 == d || index($0, d "/") == 1')
  [[ -z "$m" ]] || die "something is mounted inside $1 (not by this script):
$m
test-blender4: unmount it first (umount -R $1)"
}

# Runs a command inside the chroot with all mounts; the build folder is
# mounted only when $2 is given.
in_chroot() {
  local src=$1 build=$2; shift 2
  unshare --mount --pid --fork --kill-child --propagation private \
    "$repo/tools/test-blender4.sh" --in-namespace "$chroot_dir" "$src" "$build" "$@"
}

# The host's Debian mirror: the first http(s) URI of an enabled "deb" entry
# that is not a security archive, in apt's own order (sources.list, then
# sources.list.d/*.list and *.sources).
host_mirror() {
  local f
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [[ -f "$f" ]] || continue
    awk '$1 == "deb" {
           i = 2; if ($i ~ /^\[/) { while (i <= NF && $i !~ /\]$/) i++; i++ }
           if ($i ~ /^https?:\/\// && $(i + 1) !~ /-security/ && $i !~ /security/) { print $i; exit }
         }' "$f"
  done
  for f in /etc/apt/sources.list.d/*.sources; do
    [[ -f "$f" ]] || continue
    awk 'function flush() {
           if (!done && types ~ /(^| )deb( |$)/ && enabled != "no" && suites !~ /-security/) {
             n = split(uris, u, " ")
             for (k = 1; k <= n; k++)
               if (u[k] ~ /^https?:\/\// && u[k] !~ /security/) { print u[k]; done = 1; break }
           }
           types = uris = suites = enabled = ""
         }
         /^[ \t]*#/ { next }
         /^[ \t]*$/ { flush(); next }
         { key = tolower($1); $1 = "" }
         key == "types:" { types = $0 } key == "uris:" { uris = $0 }
         key == "suites:" { suites = $0 } key == "enabled:" { enabled = tolower($2) }
         END { flush() }' "$f"
  done
}

# --------------------------------------------------------------- --remove
if [[ "${1:-}" == "--remove" ]]; then
  exec 9>"$chroot_dir.lock"
  flock -n 9 || die "$chroot_dir is in use by another run"
  for d in "$chroot_dir" "$chroot_dir.partial"; do
    [[ -e "$d" ]] || continue
    check_no_mounts "$d"
    rm -rf --one-file-system "$d"
    say "removed $d"
  done
  rm -f "$chroot_dir.debootstrap.log" "$chroot_dir.apt.log"   # the .lock stays: others may wait on it
  exit 0
fi

# ------------------------------------------------------------ the chroot
# Packages: the stamp is written only after all of them are installed; dpkg's
# database is read from the host (no chroot, no mounts, a fraction of a
# second), so a package added to PACKAGES above is installed on the next run.
missing=()
check_packages() {
  local pkg status
  missing=()
  for pkg in "${PACKAGES[@]}"; do
    status=$(dpkg-query --admindir="$chroot_dir/var/lib/dpkg" -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)
    [[ "$status" == installed ]] || missing+=("$pkg")
  done
  [[ -f "$chroot_dir/$STAMP" && ${#missing[@]} -eq 0 ]]
}

# Runs share a ready chroot (shared lock); one run at a time creates or
# completes it (exclusive lock).
exec 9>"$chroot_dir.lock"
lock() {
  flock -n "$@" 9 && return 0
  say "waiting for another run that uses $chroot_dir ($chroot_dir.lock)"
  flock "$@" 9
}
lock -s
if [[ -d "$chroot_dir" ]] && check_packages; then
  ready=1
else
  ready=0
  lock -x
fi

if [[ $ready -eq 0 && ! -d "$chroot_dir" ]]; then
  # debootstrap and Debian's keys on the host, like every other package.
  "$repo/tools/install-deps.sh" --chroot || die "could not install debootstrap on the host"
  [[ -e /usr/share/debootstrap/scripts/$SUITE ]] \
    || die "this debootstrap does not know $SUITE: update it (apt-get install debootstrap)"
  keyring=/usr/share/keyrings/debian-archive-keyring.gpg
  [[ -f "$keyring" ]] || die "$keyring is missing: apt-get install debian-archive-keyring"
  mirror=${PHOS_DEBIAN_MIRROR:-$(host_mirror | head -n 1)}
  [[ -n "$mirror" ]] || die "no Debian mirror found in /etc/apt/sources.list{,.d/*}: set PHOS_DEBIAN_MIRROR=http://.../debian"

  # debootstrap fills $chroot_dir.partial, renamed when complete: an
  # interrupted first run leaves only .partial, which the next run deletes.
  partial="$chroot_dir.partial"
  if [[ -e "$partial" ]]; then
    check_no_mounts "$partial"
    say "removing the unfinished $partial of an interrupted run"
    rm -rf --one-file-system "$partial"
  fi
  mkdir -p "$(dirname "$chroot_dir")"
  say "creating the $SUITE_NAME chroot $chroot_dir from $mirror (a few minutes, once)"
  t=$(date +%s)
  # In a private mount namespace too: the mounts debootstrap makes in the
  # target go away with it even when it is killed.
  if ! unshare --mount --propagation private \
      debootstrap --variant=minbase --keyring="$keyring" "$SUITE" "$partial" "$mirror" \
      >"$chroot_dir.debootstrap.log" 2>&1; then
    tail -n 25 "$chroot_dir.debootstrap.log" >&2
    die "debootstrap failed (log: $chroot_dir.debootstrap.log). If the Release signature
test-blender4: does not verify, the host needs a debian-archive-keyring with the current archive keys
test-blender4: (bookworm's 2023.3+deb12u2 or later: apt-get install debian-archive-keyring)."
  fi
  mkdir -p "$partial/etc/apt/apt.conf.d" "$partial/usr/sbin"
  printf 'APT::Install-Recommends "false";\nAPT::Install-Suggests "false";\nAcquire::Languages "none";\n' \
    >"$partial/etc/apt/apt.conf.d/90phos"
  if [[ "$SUITE" == sid ]]; then
    # Unstable's Release file is valid for a week only; a mirror or cache
    # that lags behind the archive by more must still serve this chroot.
    echo 'Acquire::Check-Valid-Until "false";' >>"$partial/etc/apt/apt.conf.d/90phos"
  fi
  printf '#!/bin/sh\nexit 101\n' >"$partial/usr/sbin/policy-rc.d"   # never start services
  chmod 755 "$partial/usr/sbin/policy-rc.d"
  mv "$partial" "$chroot_dir"
  say "debootstrap done in $(elapsed "$t")"
fi
check_no_mounts "$chroot_dir"
mkdir -p "$chroot_dir/phos-src" "$chroot_dir/phos-build"

if [[ $ready -eq 0 ]] && ! check_packages; then
  say "installing in the chroot: ${missing[*]:-(checking all)} (log: $chroot_dir.apt.log)"
  t=$(date +%s)
  rm -f "$chroot_dir/$STAMP"
  if ! in_chroot "" "" /bin/sh -ec "apt-get update
      dpkg --configure -a
      apt-get install -y --no-install-recommends ${PACKAGES[*]}
      apt-get clean" >"$chroot_dir.apt.log" 2>&1; then
    tail -n 25 "$chroot_dir.apt.log" >&2
    die "installing packages in the chroot failed (log: $chroot_dir.apt.log); rerun to retry, or start over with: tools/test-blender4.sh --remove"
  fi
  mkdir -p "$(dirname "$chroot_dir/$STAMP")"
  printf '%s\n' "${PACKAGES[@]}" >"$chroot_dir/$STAMP"
  say "packages installed in $(elapsed "$t")"
fi
[[ $ready -eq 1 ]] || lock -s   # set up: other runs may use the chroot alongside
say "chroot ready ($(elapsed "$t_start"))"

mkdir -p "$build_dir"

if [[ "${1:-}" == "--prepare" ]]; then
  shift
  for version in "$@"; do
    in_chroot "$repo" "$build_dir" /bin/sh -ec "cd /phos-src
      PHOS_BPY_DIR=/phos-build/bpy tools/bpy-env.sh '$version' '/phos-build/bpy/$version'" \
      || die "Blender $version (bpy) could not be set up in the chroot"
  done
  check_no_mounts "$chroot_dir"
  exit 0
fi

if [[ "${1:-}" == "--shell" ]]; then
  say "shell in $chroot_dir: checkout (read-only) at /phos-src, build folder at /phos-build"
  rc=0; in_chroot "$repo" "$build_dir" /bin/bash -i || rc=$?
  check_no_mounts "$chroot_dir"
  exit "$rc"
fi

bpy_version="" bpy_run="" gui_only=""
if [[ "${1:-}" == "--gui" ]]; then
  gui_only=1
  shift
  [[ $# -eq 0 ]] || die "--gui takes no pytest arguments"
elif [[ "${1:-}" == "--bpy" || "${1:-}" == "--bpy-run" ]]; then
  [[ "$1" == "--bpy-run" ]] && bpy_run=1
  bpy_version=${2:?usage: test-blender4.sh --bpy VERSION [pytest args] | --bpy-run VERSION ARGS...}
  shift 2
fi
[[ $# -gt 0 || -n "$bpy_run" ]] || set -- -q   # pytest args
# Inside: Embree-4 build in /phos-build; libphos.so goes to /phos-build/lib
# (not the checkout's addon/phos/lib, which belongs to the host's build), and
# the add-on from the checkout loads it through PHOS_LIBRARY.
# shellcheck disable=SC2016  # expanded inside the chroot
inner='set -u
now() { date +%s; }
dur() { local s=$(( $(now) - $1 )); printf "%dm%02ds" $((s / 60)) $((s % 60)); }
say() { echo "test-blender4: $*"; }
say "$(blender --version 2>/dev/null | head -n 1), Embree $(dpkg-query -W -f="\${Version}" libembree-dev), $(python3 --version)"
t=$(now)
cmake -S /phos-src -B /phos-build -DCMAKE_BUILD_TYPE=Release -DPHOS_ADDON_LIB_DIR=/phos-build/lib >/phos-build/cmake.log \
  || { cat /phos-build/cmake.log; say "cmake configure failed"; exit 1; }
grep "Phos:" /phos-build/cmake.log || true
cmake --build /phos-build -j "$JOBS" ${GUI_ONLY:+--target phos} || { say "build failed"; exit 1; }
/phos-src/tools/check-exports.sh /phos-build/lib/libphos.so || exit 1
say "build: $(dur $t)"
rc=0
if [[ -n "$BPY_RUN" ]]; then
  # A command line for the official Blender (tools/bpy-run.sh): the add-on
  # from the checkout, with the Embree-4 library of this build.
  PHOS_BPY_DIR=/phos-build/bpy /phos-src/tools/bpy-env.sh "$BPY_VERSION" "/phos-build/bpy/$BPY_VERSION" >&2 || exit 1
  cd /phos-src && PHOS_LIBRARY=/phos-build/lib/libphos.so "/phos-build/bpy/$BPY_VERSION/blender" "$@"
  exit $?
fi
if [[ -n "$BPY_VERSION" ]]; then
  # The official Blender as a Python module (tools/test-bpy.sh), with the
  # add-on folder of this build (its Embree-4 libphos.so).
  stage=/phos-build/bpy-addon
  rm -rf "$stage" && mkdir -p "$stage" && cp -r /phos-src/addon/phos "$stage/phos" \
    && rm -rf "$stage/phos/lib" && mkdir "$stage/phos/lib" && cp /phos-build/lib/libphos.so "$stage/phos/lib/" \
    || { say "staging the add-on failed"; exit 1; }
  cd /phos-src && PHOS_BPY_DIR=/phos-build/bpy tools/test-bpy.sh --here "$BPY_VERSION" "$stage/phos" "$@"
  exit $?
fi
mkdir -p /phos-build/blender-user
if [[ -z "$GUI_ONLY" ]]; then
  t=$(now)
  (cd /phos-build && ctest --output-on-failure -j "$JOBS") || { rc=1; say "C tests FAILED"; }
  say "C tests: $(dur $t)"
  t=$(now)
  PHOS_LIBRARY=/phos-build/lib/libphos.so \
  BLENDER_USER_SCRIPTS=/phos-build/blender-user/scripts \
  BLENDER_USER_CONFIG=/phos-build/blender-user/config \
    blender -b --factory-startup --python-exit-code 1 \
      --python /phos-src/tests/blender/run_tests.py -- "$@" || { rc=1; say "Blender tests FAILED"; }
  say "Blender tests: $(dur $t)"
fi
# The GUI tests (viewport, previews) in the window of Blender on Xvfb,
# with the whole suite (not for a chosen subset of tests) or alone (--gui).
if [[ -n "$GUI_ONLY" || "$*" == "-q" ]]; then
  t=$(now)
  PHOS_LIBRARY=/phos-build/lib/libphos.so \
  BLENDER_USER_SCRIPTS=/phos-build/blender-user/scripts \
  BLENDER_USER_CONFIG=/phos-build/blender-user/config \
    /phos-src/tools/test-gui.sh blender /phos-build/gui || { rc=1; say "GUI tests FAILED"; }
  say "GUI tests: $(dur $t)"
fi
# The 4.2+ extension: the zip of tools/package.py with this Embree-4
# libphos.so, installed with `blender --command extension install-file` into
# throw-away user folders and rendered from there, PHOS_LIBRARY unset.
t=$(now)
stage=$(mktemp -d /tmp/phos-ext.XXXXXX)
cp -r /phos-src/addon/phos "$stage/phos" && rm -rf "$stage/phos/lib" && mkdir "$stage/phos/lib" \
  && cp /phos-build/lib/libphos.so "$stage/phos/lib/" \
  && python3 /phos-src/tools/package.py --addon "$stage/phos" --dist /phos-build/dist \
  && /phos-src/tools/check-addon.sh --extension "/phos-build/dist/phos-$(python3 /phos-src/tools/version.py).zip" \
  || { rc=1; say "extension check FAILED"; }
rm -rf "$stage"
say "extension install check: $(dur $t)"
exit $rc'
rc=0
in_chroot "$repo" "$build_dir" /usr/bin/env BPY_VERSION="$bpy_version" BPY_RUN="$bpy_run" GUI_ONLY="$gui_only" \
  /bin/bash -c "$inner" inner "$@" || rc=$?
check_no_mounts "$chroot_dir"
what="$SUITE_NAME's Blender"
[[ -z "$gui_only" ]] || what="$SUITE_NAME's Blender, GUI tests"
[[ -z "$bpy_version" ]] || what="Blender $bpy_version (bpy)"
if [[ $rc -eq 0 ]]; then
  say "passed under $what / Embree 4 (total $(elapsed "$t_start"); no mounts left in $chroot_dir)"
else
  say "FAILED (exit $rc; total $(elapsed "$t_start"); no mounts left in $chroot_dir)"
fi
exit "$rc"
