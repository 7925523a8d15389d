# SPDX-License-Identifier: GPL-3.0-or-later
"""Run the Blender tests inside Blender:

    blender -b --factory-startup --python-exit-code 1 \
        --python tests/blender/run_tests.py -- [pytest args]

Enables the Phos add-on from the source tree (<repo>/addon), then runs pytest
on tests/blender with the given arguments and exits with pytest's code.
Examples of pytest args: `-k parity`, `-x -v`, `test_register.py`.
"""

import os
import sys

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, TESTS_DIR)


def main():
    import pytest

    import phostest

    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if phostest.enable_addon() is None:
        print("run_tests: the add-on could not be enabled from %s; tests that need it will fail"
              % phostest.ADDON_DIR, flush=True)
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
