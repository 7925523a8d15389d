# SPDX-License-Identifier: GPL-3.0-or-later
"""Run the Blender tests inside Blender:

    blender -b --factory-startup --python-exit-code 1 \
        --python tests/blender/run_tests.py -- [--extension ZIP] [pytest args]

Enables the Phos add-on from the source tree (<repo>/addon), then runs pytest
on tests/blender with the given arguments and exits with pytest's code.
Examples of pytest args: `-k parity`, `-x -v`, `test_register.py`.

--extension ZIP (Blender 4.2+): test the add-on as a user installs it
instead: the zip of tools/package.py is installed with Blender's own
extension installer into the user repository "user_default" of the user
folders this Blender uses (point BLENDER_USER_* at throw-away folders), and
every test, and every Blender a test starts, uses that copy
(PHOS_ADDON_MODULE = bl_ext.user_default.phos).
"""

import os
import sys

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TESTS_DIR)


EXTENSION_REPO = "user_default"


def install_extension(zip_path):
    """Install the add-on zip as an extension, as Blender's installer does
    (Preferences › Get Extensions › Install from Disk); returns its module."""
    import bpy
    bpy.ops.extensions.package_install_files(filepath=os.path.abspath(zip_path), repo=EXTENSION_REPO,
                                             enable_on_install=False)
    return "bl_ext.%s.phos" % EXTENSION_REPO


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if argv[:1] == ["--extension"]:
        if len(argv) < 2:
            print("run_tests: --extension needs the add-on zip", flush=True)
            return 2
        os.environ["PHOS_ADDON_MODULE"] = install_extension(argv[1])
        argv = argv[2:]

    import pytest

    import phostest

    if phostest.enable_addon() is None:
        print("run_tests: the add-on %s could not be enabled%s; tests that need it will fail"
              % (phostest.ADDON_NAME, " from " + phostest.ADDON_DIR if phostest.FROM_SOURCE_TREE else ""),
              flush=True)
    print("run_tests: Blender %s, add-on %s from %s" % (
        __import__("bpy").app.version_string, phostest.ADDON_NAME,
        os.path.dirname(getattr(sys.modules.get(phostest.ADDON_NAME), "__file__", "") or "?")), flush=True)
    # Relative test paths given on the command line are relative to this folder.
    args = [os.path.join(TESTS_DIR, a) if a.endswith(".py") and not os.path.isabs(a)
            and not os.path.exists(a) else a for a in argv]
    if not any(a.endswith(".py") or os.path.isdir(a) or "::" in a for a in args):
        args.append(TESTS_DIR)
    # The cache would land in the source tree; -p no:cacheprovider keeps it clean.
    args = ["-p", "no:cacheprovider", "--rootdir", TESTS_DIR] + args
    return int(pytest.main(args))


if __name__ == "__main__":
    sys.exit(main())
