#!/usr/bin/env python3
"""Builds dist/phos-<version>.zip: the add-on folder phos/ with its library.

The zip holds one top-level folder, phos/, which is what both installers
expect: Blender 3.x-4.1 (Preferences > Add-ons > Install, or
bpy.ops.preferences.addon_install) extracts it into scripts/addons/, and
Blender 4.2+ (Get Extensions > Install from Disk) finds
phos/blender_manifest.toml one folder down.

  tools/package.py [--addon addon/phos] [--dist dist]
"""
import argparse
import ast
import os
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXCLUDED_DIRS = {"__pycache__", ".pytest_cache"}
EXCLUDED_SUFFIXES = {".pyc", ".pyo", ".blend1", ".orig", ".rej", ".tmp"}
# Fields Blender 4.2's extension installer requires in the manifest.
MANIFEST_REQUIRED = ("schema_version", "id", "version", "name", "tagline",
                     "maintainer", "type", "blender_version_min", "license")


def fail(msg):
    print("package: " + msg, file=sys.stderr)
    sys.exit(1)


def check_addon(addon):
    init = addon / "__init__.py"
    if not init.is_file():
        fail("%s is missing" % init)
    bl_info = None
    for node in ast.parse(init.read_text(), str(init)).body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "bl_info" for t in node.targets):
            bl_info = ast.literal_eval(node.value)
    if not bl_info:
        fail("%s has no bl_info (needed by Blender before 4.2)" % init)
    if tuple(bl_info.get("blender", (99,))) > (3, 4, 0):
        fail("bl_info['blender'] = %r: must be at most (3, 4, 0)" % (bl_info.get("blender"),))

    manifest = addon / "blender_manifest.toml"
    if not manifest.is_file():
        fail("%s is missing (needed by Blender 4.2+)" % manifest)
    with open(manifest, "rb") as fh:
        data = tomllib.load(fh)
    missing = [k for k in MANIFEST_REQUIRED if k not in data]
    if missing:
        fail("%s lacks %s" % (manifest, ", ".join(missing)))
    if data["id"] != addon.name:
        fail("manifest id %r differs from the folder name %r" % (data["id"], addon.name))
    if data["type"] != "add-on":
        fail("manifest type must be 'add-on'")
    # Blender 4.2 refuses a tagline over 64 characters or ending in punctuation.
    tagline = data["tagline"]
    if len(tagline) > 64 or tagline[-1:] in (".", "!", "?", ",", ";", ":"):
        fail("manifest tagline must be at most 64 characters without final punctuation")

    lib = addon / "lib" / "libphos.so"
    if not lib.is_file():
        fail("%s is missing: run 'make build' first" % lib)


def collect(addon):
    files = []
    for dirpath, dirnames, filenames in os.walk(addon):
        dirnames[:] = sorted(d for d in dirnames
                             if d not in EXCLUDED_DIRS and not d.startswith("."))
        for name in sorted(filenames):
            if name.startswith(".") or Path(name).suffix in EXCLUDED_SUFFIXES:
                continue
            files.append(Path(dirpath) / name)
    return files


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--addon", default=str(ROOT / "addon" / "phos"))
    parser.add_argument("--dist", default=str(ROOT / "dist"))
    args = parser.parse_args()
    addon = Path(args.addon).resolve()
    dist = Path(args.dist).resolve()

    check_addon(addon)
    version = subprocess.run([sys.executable, str(ROOT / "tools" / "version.py")],
                             stdout=subprocess.PIPE, text=True)
    if version.returncode != 0:
        sys.exit(1)
    version = version.stdout.strip()

    dist.mkdir(parents=True, exist_ok=True)
    out = dist / ("phos-%s.zip" % version)
    tmp = out.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zf:
        for path in collect(addon):
            zf.write(path, Path(addon.name) / path.relative_to(addon))
    os.replace(tmp, out)

    with zipfile.ZipFile(out) as zf:
        names = zf.namelist()
    print("package: %s (%d files, %.1f MiB)" % (
        out.relative_to(ROOT) if out.is_relative_to(ROOT) else out,
        len(names), out.stat().st_size / 2**20))


if __name__ == "__main__":
    main()
