#!/usr/bin/env bash
# Fails if libphos exports any symbol that does not start with phos_.
# Everything else must stay hidden so the library cannot clash with the
# symbols of Blender or of the libraries Blender has loaded.
#
#   tools/check-exports.sh [path/to/libphos.so]   (default: addon/phos/lib/libphos.so)
set -euo pipefail
lib=${1:-"$(dirname "$0")/../addon/phos/lib/libphos.so"}

if [[ ! -f "$lib" ]]; then
  echo "check-exports: $lib not found (run 'make build' first)" >&2
  exit 1
fi

# Defined dynamic symbols: "ADDRESS TYPE NAME". Skip the linker's own
# markers (_init/_fini and friends), which are not part of any API.
symbols=$(nm -D --defined-only "$lib" | awk 'NF >= 3 { print $3 }' \
  | grep -Ev '^(_init|_fini|_edata|_end|__bss_start)$' || true)

if [[ -z "$symbols" ]]; then
  echo "check-exports: $lib exports no symbols at all" >&2
  exit 1
fi

bad=$(printf '%s\n' "$symbols" | grep -v '^phos_' || true)
if [[ -n "$bad" ]]; then
  echo "check-exports: $lib exports symbols outside the phos_ namespace:" >&2
  printf '  %s\n' $bad >&2
  exit 1
fi

echo "check-exports: $(printf '%s\n' "$symbols" | wc -l) symbols, all phos_*"
