#!/usr/bin/env python3
"""Prints Phos's version and checks that every place that states it agrees.

The version is written in four places, each read by a different consumer:
  CMakeLists.txt             project(phos VERSION x.y.z)   the build
  core/include/phos.h        PHOS_VERSION_MAJOR/MINOR/PATCH the library (checked by the add-on)
  addon/phos/__init__.py     bl_info["version"]            Blender 3.x-4.1 add-on list
  addon/phos/blender_manifest.toml  version = "x.y.z"      Blender 4.2+ extension

  tools/version.py           print the version (exit 1 if the places disagree)
"""
import ast
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def from_cmake():
    text = (ROOT / "CMakeLists.txt").read_text()
    m = re.search(r"project\s*\(\s*phos\b[^)]*\bVERSION\s+([0-9]+\.[0-9]+\.[0-9]+)", text, re.I)
    return m.group(1) if m else None


def from_header():
    path = ROOT / "core/include/phos.h"
    if not path.exists():
        return None
    text = path.read_text()
    parts = []
    for name in ("MAJOR", "MINOR", "PATCH"):
        m = re.search(r"#define\s+PHOS_VERSION_%s\s+([0-9]+)" % name, text)
        if not m:
            return None
        parts.append(m.group(1))
    return ".".join(parts)


def from_bl_info():
    path = ROOT / "addon/phos/__init__.py"
    if not path.exists():
        return None
    tree = ast.parse(path.read_text(), str(path))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "bl_info" for t in node.targets):
            info = ast.literal_eval(node.value)
            version = info.get("version")
            return ".".join(str(v) for v in version) if version else None
    return None


def from_manifest():
    path = ROOT / "addon/phos/blender_manifest.toml"
    if not path.exists():
        return None
    with open(path, "rb") as fh:
        return tomllib.load(fh).get("version")


def main():
    found = {
        "CMakeLists.txt": from_cmake(),
        "core/include/phos.h": from_header(),
        "addon/phos/__init__.py (bl_info)": from_bl_info(),
        "addon/phos/blender_manifest.toml": from_manifest(),
    }
    versions = {v for v in found.values() if v}
    if not versions:
        print("version.py: no version found", file=sys.stderr)
        return 1
    if len(versions) > 1:
        print("version.py: the version is not the same everywhere:", file=sys.stderr)
        for where, v in found.items():
            print("  %-36s %s" % (where, v or "(not found)"), file=sys.stderr)
        return 1
    print(versions.pop())
    return 0


if __name__ == "__main__":
    sys.exit(main())
