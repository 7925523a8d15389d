# Phos — build, test, render and package.
#
#   make render [SCENE=name] [SAMPLES=n]  render scenes/<name>.py to out/<name>.png/.exr
#               [ARGS="--engine CYCLES"]  (more options of the scene script)
#   make test                             binding up to date, C unit tests, Blender test suite
#   make binding                          regenerate addon/phos/phos_h.py from phos.h
#   make test-blender4                    the same under Blender 4.3 / Embree 4 in a
#               [PHOS_CHROOT_DIR=dir]     Debian 13 chroot (root; default /var/tmp/...)
#   make test-blender5                    the GUI tests in Blender 5.2's window, in a Debian
#               [PHOS_SID_CHROOT_DIR=dir] unstable chroot (root; default /var/tmp/...)
#   make test-blender-latest              the Blender tests against the official builds of
#                                         tools/bpy-versions.txt (4.5 LTS, newest 5.x: bpy
#                                         from PyPI), the add-on installed as an extension
#   make install | uninstall              add-on into the user's Blender
#   make package                          dist/phos-<version>.zip
#   make bench [QUICK=1]                  Phos against Cycles, raw Embree and nanoflann in one
#               [BENCH_SCENES_ALL=...]    run: out/bench/ (CSV, plots, summary.md); cached
#                                         references (docs/benchmarks.md: hours, most of
#                                         it references; QUICK=1 a few minutes)
#   make bench-official                   the part against official Cycles (guiding, OIDN) alone
#   make bench-convergence [QUICK=1]      samplers, adaptive sampling and filters against
#                                         cached references alone (bench/convergence.py)
#   make bench-kdtree [BENCH_ARGS=...]    the kd-tree benchmark alone
#   make bench-farm                       a farm's cache task against caches per frame
#                                         (bench/farm.py, docs/farm.md; part of make bench)
#   make bench-defaults                   PHOTON settings swept against cached Cycles
#               [BENCH_SCENES=...]        references, ranked by error per second, and
#                                         the defaults against Cycles at equal time
#                                         (docs/benchmarks.md; about an hour)
#   make test-asan | test-tsan            the C tests built with AddressSanitizer + UBSan, or
#                                         ThreadSanitizer (build-asan/, build-tsan/)
#   make valgrind                         small PATH and PHOTON renders under memcheck: no
#                                         error, no definite leak (build-valgrind/)
#   make fuzz [FUZZ_SECONDS=60]           libFuzzer on the C API from tests/fuzz/corpus, with
#                                         clang, ASan and UBSan (build-fuzz/, out/fuzz/)
#                                         (docs/reliability.md)
#   make image-digests [DIGESTS=file]     SHA-256 of every pass of every test scene, per
#                                         integrator (compare before/after a refactoring)
#   make deps | build | clean
#
# build, test, render, install and package first install the Debian packages
# that are missing (tools/install-deps.sh): a fresh Debian 12 needs only make.

SHELL := /bin/bash
MAKEFLAGS += --no-print-directory
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := build

BLENDER   ?= blender
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS      ?= $(shell nproc 2>/dev/null || echo 2)
SCENE     ?= cornell_box
SAMPLES   ?=
ARGS      ?=
PYTEST_ARGS ?= -q

ADDON_LIB_DIR := $(CURDIR)/addon/phos/lib
BLENDER_RUN := $(BLENDER) -b --factory-startup --python-exit-code 1

# Tests and renders run against the add-on in this tree, with Blender's user
# folders redirected into the build folder: an add-on installed with
# `make install`, or the user's preferences, cannot change their outcome.
BLENDER_ISOLATED := BLENDER_USER_SCRIPTS=$(CURDIR)/$(BUILD_DIR)/blender-user/scripts \
                    BLENDER_USER_CONFIG=$(CURDIR)/$(BUILD_DIR)/blender-user/config

PHOS_CHROOT_DIR ?= /var/tmp/phos-trixie-chroot
PHOS_SID_CHROOT_DIR ?= /var/tmp/phos-sid-chroot

.PHONY: test-asan test-tsan valgrind fuzz
.PHONY: deps build binding check-binding test test-gui test-blender4 test-blender5 test-blender-latest bench bench-official bench-convergence bench-programs bench-kdtree bench-defaults bench-farm render image-digests install uninstall package clean help

help:
	@sed -n '3,/^$$/p' Makefile | sed 's/^# \{0,1\}//'

deps:
	@tools/install-deps.sh

build: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) \
	  -DPHOS_ADDON_LIB_DIR=$(ADDON_LIB_DIR)
	cmake --build $(BUILD_DIR) -j $(JOBS)

# The add-on's ctypes binding is generated from phos.h and committed, so the
# add-on works without the generator (tools/gen_binding.py).
BINDING := addon/phos/phos_h.py
binding:
	python3 tools/gen_binding.py --output $(BINDING)

check-binding: deps
	@tmp=$$(mktemp) && trap 'rm -f "$$tmp"' EXIT && \
	python3 tools/gen_binding.py --output "$$tmp" && \
	if ! diff -u $(BINDING) "$$tmp"; then \
	  echo "check-binding: $(BINDING) is out of date with core/include/phos.h: run 'make binding'" >&2; \
	  exit 1; \
	fi; \
	echo "check-binding: $(BINDING) matches core/include/phos.h"

test: check-binding build
	tools/check-exports.sh $(ADDON_LIB_DIR)/libphos.so
	@echo "version: $$(python3 tools/version.py) (CMake, phos.h, bl_info and manifest agree)"
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)
	$(BLENDER_ISOLATED) $(BLENDER_RUN) --python tests/blender/run_tests.py -- $(PYTEST_ARGS)

# Blender's GUI under Xvfb with software OpenGL: a 3D view in Rendered
# shading with Phos (tests/gui/test_viewport.py; skipped where Xvfb cannot run).
test-gui: build
	@tools/install-deps.sh --gui
	$(BLENDER_ISOLATED) tools/test-gui.sh $(BLENDER) $(CURDIR)/$(BUILD_DIR)/gui

# The C tests under the sanitizers (docs/reliability.md): RelWithDebInfo, so
# reports have lines; a report is an error (halt_on_error, and UBSan does
# not recover, see CMakeLists.txt). LeakSanitizer runs with ASan. Embree is
# not instrumented; TSan's suppressions name only its threads' internals
# (tests/sanitizers/tsan.supp). PHOS_TEST_SANITIZER leaves the tests whose
# time is statistics to the plain build (tests/c/test_util.h).
SANITIZER_ENV := PHOS_TEST_SANITIZER=1 ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=1 \
                 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
                 TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:suppressions=$(CURDIR)/tests/sanitizers/tsan.supp
test-asan: deps
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHOS_SANITIZE=address
	cmake --build build-asan -j $(JOBS)
	cd build-asan && $(SANITIZER_ENV) ctest --output-on-failure -j $(JOBS)

test-tsan: deps
	cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHOS_SANITIZE=thread
	cmake --build build-tsan -j $(JOBS)
	cd build-tsan && $(SANITIZER_ENV) ctest --output-on-failure -j $(JOBS)

# Memcheck of tests/c/test_lifetimes.c (small renders of both integrators,
# cache files, cancels, failures): any error or definitely lost block fails.
VALGRIND_TEST := build-valgrind/tests/c/test_lifetimes
valgrind:
	@tools/install-deps.sh --reliability
	cmake -S . -B build-valgrind -DCMAKE_BUILD_TYPE=RelWithDebInfo
	cmake --build build-valgrind -j $(JOBS) --target test_lifetimes
	valgrind --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite \
	  --show-leak-kinds=definite $(VALGRIND_TEST)

# libFuzzer (tests/fuzz/fuzz_api.c): new inputs go to out/fuzz/corpus, the
# seeds in tests/fuzz/corpus are only read; a crash, leak or hang is written
# to out/fuzz/ as crash-*, leak-* or timeout-* and fails the target. A
# single allocation may exceed the resident limit: a 65536 × 10001 film
# (10 GB) fits this machine, so the core accepts it and the kernel maps it
# lazily; resident memory is what must stay bounded. The core refuses any
# render larger than the memory and swap there are, so no allocation it
# makes may exceed that (FUZZ_MALLOC_LIMIT_MB). ASan's bookkeeping of such
# a film takes seconds, hence the 30 s per input.
FUZZ_SECONDS ?= 60
FUZZ_MALLOC_LIMIT_MB ?= $(shell awk '/^(MemTotal|SwapTotal):/ {kb += $$2} END {print int(kb / 1024)}' /proc/meminfo)
fuzz:
	@tools/install-deps.sh --reliability
	CC=clang cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHOS_SANITIZE=address \
	  -DPHOS_BUILD_FUZZ=ON -DPHOS_BUILD_TESTS=OFF
	cmake --build build-fuzz -j $(JOBS) --target fuzz_api
	mkdir -p out/fuzz/corpus
	$(SANITIZER_ENV) build-fuzz/tests/fuzz/fuzz_api -max_total_time=$(FUZZ_SECONDS) -timeout=30 \
	  -rss_limit_mb=4096 -malloc_limit_mb=$(FUZZ_MALLOC_LIMIT_MB) -print_final_stats=1 -artifact_prefix=out/fuzz/ out/fuzz/corpus tests/fuzz/corpus

# Debian 13 chroot made once with debootstrap, then reused; the build goes to
# build-trixie/, never to build/ or addon/phos/lib. See tools/test-blender4.sh.
test-blender4:
	PHOS_CHROOT_SUITE=trixie PHOS_CHROOT_DIR=$(PHOS_CHROOT_DIR) JOBS=$(JOBS) tools/test-blender4.sh $(PYTEST_ARGS)

# The GUI tests in the window of Blender 5.2, from a Debian unstable chroot
# made the same way (build-sid/): the official 5.x builds here are Python
# modules, without a window.
test-blender5:
	PHOS_CHROOT_SUITE=sid PHOS_CHROOT_DIR=$(PHOS_SID_CHROOT_DIR) JOBS=$(JOBS) tools/test-blender4.sh --gui

# The official Blender builds artists run (tools/bpy-versions.txt): each one's
# Python virtual environment under build/bpy/ (or the chroot's build folder),
# the extension zip installed as a user installs it, the whole Blender suite
# with that release's own Cycles as the reference (tools/test-bpy.sh).
test-blender-latest: build
	PHOS_CHROOT_DIR=$(PHOS_CHROOT_DIR) JOBS=$(JOBS) tools/test-bpy.sh $(PYTEST_ARGS)

# Release build of bench/ in its own folder, so that PHOS_BUILD_BENCH=ON never
# lands in $(BUILD_DIR)'s cache (and C++ never in `make build` or `make test`).
# BENCH_ARGS: --photons N --queries Q --k K (default 1000000, 100000, 50 and 500).
BENCH_DIR  ?= $(BUILD_DIR)/bench-release
BENCH_ARGS ?=
bench-programs:
	@tools/install-deps.sh --bench
	cmake -S . -B $(BENCH_DIR) -DCMAKE_BUILD_TYPE=Release -DPHOS_BUILD_BENCH=ON -DPHOS_BUILD_TESTS=OFF
	cmake --build $(BENCH_DIR) -j $(JOBS) --target bench_kdtree bench_core

bench-kdtree: bench-programs
	$(BENCH_DIR)/bench/bench_kdtree $(BENCH_ARGS)

# What a farm's cache task saves (bench/farm.py, docs/farm.md): an 8-frame
# walkthrough with caches per frame against one cache task and frames that
# load it; its table goes to $(BENCH_OUT)/farm.md.
bench-farm: build
	mkdir -p $(BENCH_OUT)
	/usr/bin/python3 bench/farm.py --out $(BENCH_OUT)/farm | tee $(BENCH_OUT)/farm.md

# Image quality against time (bench/quality.py, docs/benchmarks.md): the
# Cycles references are cached in BENCH_REF_DIR and only extended, never
# re-rendered; the CSVs go to out/bench/.
BENCH_REF_DIR    ?= $(HOME)/.cache/phos-bench
BENCH_SCENES     ?= cornell_box sunlit_room
BENCH_RESOLUTION ?= 128 128
BENCH_REF_CHUNKS ?= 32
BENCH_GRID       ?= samples=16,32,64,128,256 final_gather_rays=1,2,4,8 global_photons=50000,200000,800000
BENCH_QUALITY := $(BLENDER_ISOLATED) $(BLENDER_RUN) --python bench/quality.py --
BENCH_QUIET   := grep --line-buffered -v '^Fra:'
bench-defaults: build
	mkdir -p out/bench
	for s in $(BENCH_SCENES); do \
	  $(BENCH_QUALITY) reference --scene $$s --resolution $(BENCH_RESOLUTION) \
	    --chunks $(BENCH_REF_CHUNKS) --reference-dir $(BENCH_REF_DIR) | $(BENCH_QUIET); \
	  $(BENCH_QUALITY) sweep --scene $$s --resolution $(BENCH_RESOLUTION) --reference-dir $(BENCH_REF_DIR) \
	    --grid "$(BENCH_GRID)" --csv out/bench/sweep_$$s.csv | $(BENCH_QUIET); \
	  $(BENCH_QUALITY) equal-time --scene $$s --resolution $(BENCH_RESOLUTION) --reference-dir $(BENCH_REF_DIR) \
	    --csv out/bench/equal_time_$$s.csv | $(BENCH_QUIET); \
	done
	python3 bench/defaults_report.py $(foreach s,$(BENCH_SCENES),out/bench/sweep_$(s).csv)

# Everything issue by issue asks of the benchmark, in one run; the tables
# and plots land in out/bench/ (summary.md). Plots use Debian's Python,
# which has numpy and matplotlib (tools/install-deps.sh --bench).
# QUICK=1: the same steps, reduced to a few minutes (one scene at 64², short
# budgets, small photon maps and meshes); its tables are for checking that
# the benchmark runs, not for docs/benchmarks.md.
ifeq ($(QUICK),1)
BENCH_SCENES_ALL ?= cornell_box
BENCH_BUDGETS    ?= 1 4
BENCH_TRIANGLES  ?= 10000 100000
BENCH_RESOLUTION := 64 64
BENCH_REF_CHUNKS := 4
BENCH_MAX_PHOTONS := 1000000
BENCH_DUMPS := 200000
BENCH_OUT := out/bench-quick
BENCH_CONVERGENCE_ARGS ?= --spp 1 4 16 --seeds 1 --thresholds 0.02 --adaptive-samples 128 --ladder 16 64 \
                          --filters NONE LOWPASS MEDIAN DIFFUSION --targets ALL INDIRECT_IRRADIANCE \
                          --filter-scenes cornell_box
else
BENCH_SCENES_ALL ?= cornell_box sunlit_room glass_sphere_caustic metal_ring procedural_materials hdr_product \
                    default_scene lamp_kinds spot_on_floor \
                    cognac_glass
BENCH_BUDGETS    ?= 4 16 64
BENCH_TRIANGLES  ?= 10000 100000 1000000 5000000
BENCH_MAX_PHOTONS := 10000000
BENCH_DUMPS := 200000 2000000
BENCH_OUT := out/bench
BENCH_CONVERGENCE_ARGS ?= --seeds 8 --adaptive-samples 1024 --filter-scenes cornell_box procedural_materials
endif
# Noise reduction as the course's slides list it: samplers, adaptive
# sampling, filters (bench/convergence.py; its references are cached too).
BENCH_CONVERGENCE := $(BLENDER_ISOLATED) $(BLENDER_RUN) --python bench/convergence.py -- --out $(BENCH_OUT) \
                     --reference-dir $(BENCH_REF_DIR) --resolution $(BENCH_RESOLUTION) \
                     --ref-chunks $(BENCH_REF_CHUNKS) $(BENCH_CONVERGENCE_ARGS)
# Issue 24's scenes (PATH and PHOTON at Cycles' error in equal time) are
# measured at equal time over BENCH_EQUAL_SEEDS seeds, here and in
# bench-official (the ratio of the mean relative MSE x time: one half-second
# render's error is one draw of a heavy-tailed error).
BENCH_OFFICIAL_EQUAL ?= default_scene lamp_kinds
BENCH_EQUAL_SEEDS ?= 8
bench: bench-programs build
	mkdir -p $(BENCH_OUT)
	$(BENCH_DIR)/bench/bench_core rays threads photons --max-photons $(BENCH_MAX_PHOTONS) --csv $(BENCH_OUT)
	for n in $(BENCH_DUMPS); do \
	  $(BENCH_DIR)/bench/bench_core dump $(BENCH_OUT)/cornell_$$n.photons $$n; done
	$(BENCH_DIR)/bench/bench_kdtree $(foreach n,$(BENCH_DUMPS),--input $(BENCH_OUT)/cornell_$(n).photons) \
	  --queries 20000 --csv $(BENCH_OUT)/kdtree.csv
	$(BLENDER_ISOLATED) $(BLENDER_RUN) --python bench/export.py -- --csv $(BENCH_OUT)/export.csv | $(BENCH_QUIET)
	@tools/install-deps.sh --gui
	$(BLENDER_ISOLATED) tools/bench-viewport.sh $(BLENDER) $(BENCH_OUT)/viewport.csv
	for s in $(BENCH_SCENES_ALL); do \
	  seeds=1; case " $(BENCH_OFFICIAL_EQUAL) " in *" $$s "*) seeds=$(BENCH_EQUAL_SEEDS);; esac; \
	  $(BENCH_QUALITY) reference --scene $$s --resolution $(BENCH_RESOLUTION) \
	    --chunks $(BENCH_REF_CHUNKS) --reference-dir $(BENCH_REF_DIR) | $(BENCH_QUIET); \
	  $(BENCH_QUALITY) bench --scene $$s --resolution $(BENCH_RESOLUTION) --reference-dir $(BENCH_REF_DIR) \
	    --budgets $(BENCH_BUDGETS) --equal-reps $$seeds --csv $(BENCH_OUT)/bench_$$s.csv | $(BENCH_QUIET); \
	done
	$(BENCH_CONVERGENCE) | $(BENCH_QUIET)
	$(BLENDER_ISOLATED) $(BLENDER_RUN) --python bench/scaling.py -- --triangles $(BENCH_TRIANGLES) \
	  --csv $(BENCH_OUT)/scaling.csv | $(BENCH_QUIET)
	$(MAKE) bench-official BENCH_OUT=$(BENCH_OUT)
	$(MAKE) bench-farm BENCH_OUT=$(BENCH_OUT)
	/usr/bin/python3 bench/plots.py $(BENCH_OUT)

bench-convergence: build
	@tools/install-deps.sh --bench
	mkdir -p $(BENCH_OUT)
	$(BENCH_CONVERGENCE) | $(BENCH_QUIET)
	/usr/bin/python3 bench/plots.py $(BENCH_OUT)

# Cycles as artists run it: the newest official build of tools/bpy-versions.txt
# (path guiding, OpenImageDenoise), each scene against a reference of that
# Cycles kept with the build (tools/bpy-run.sh: here or in the Debian 13
# chroot); Phos raw and through the Denoise node at the same time.
BENCH_OFFICIAL ?= $(shell tools/bpy-run.sh --newest)
BENCH_BPY_RUN  := tools/bpy-run.sh $(BENCH_OFFICIAL) $(BENCH_OUT) -- -b --factory-startup --python-exit-code 1 \
                  --python bench/quality.py --
bench-official: build
	mkdir -p $(BENCH_OUT)
	for s in $(BENCH_SCENES_ALL); do \
	  measure="--parts official"; \
	  case " $(BENCH_OFFICIAL_EQUAL) " in *" $$s "*) measure="--parts official equal --equal-reps $(BENCH_EQUAL_SEEDS)";; esac; \
	  $(BENCH_BPY_RUN) reference --scene $$s --resolution $(BENCH_RESOLUTION) --chunks $(BENCH_REF_CHUNKS) \
	    --reference-dir {cache}/references | $(BENCH_QUIET); \
	  $(BENCH_BPY_RUN) bench --scene $$s --resolution $(BENCH_RESOLUTION) --reference-dir {cache}/references \
	    $$measure --csv {out}/official_$$s.csv | $(BENCH_QUIET); \
	done

# Not a test: digests depend on the compiler, Embree and the CPU, so two runs
# are compared on one machine (tools/image-digests.py).
DIGESTS ?= out/image-digests.txt
DIGEST_SCENES ?= out/image-digest-scenes
image-digests: build
	$(BLENDER_ISOLATED) $(BLENDER_RUN) --python tools/image-digests.py -- $(DIGESTS) $(DIGEST_SCENES)

render: build
	@test -f scenes/$(SCENE).py || { echo "render: no scene scenes/$(SCENE).py; scenes:" \
	  $$(ls scenes/*.py 2>/dev/null | sed 's|scenes/||; s|\.py$$||' | grep -v '^_'); exit 1; }
	mkdir -p out
	$(BLENDER_ISOLATED) $(BLENDER_RUN) --python scenes/$(SCENE).py -- \
	  --render out/$(SCENE) $(if $(SAMPLES),--samples $(SAMPLES)) $(ARGS)
	@ls -l out/$(SCENE).png out/$(SCENE).exr

# Copies (not symlinks) the add-on: see tools/install-addon.sh. Then renders a
# tiny scene with `blender -b --addons phos` to prove the install works.
install: build
	BLENDER=$(BLENDER) tools/install-addon.sh
	BLENDER=$(BLENDER) tools/check-addon.sh --installed

uninstall:
	BLENDER=$(BLENDER) tools/install-addon.sh --remove

# Builds the zip, then installs it with Blender's own add-on installer into
# throw-away user folders and renders with it.
package: build
	python3 tools/package.py
	BLENDER=$(BLENDER) tools/check-addon.sh --zip dist/phos-$$(python3 tools/version.py).zip

clean:
	rm -rf $(BUILD_DIR) build-trixie build-sid build-asan build-tsan build-valgrind build-fuzz out dist $(ADDON_LIB_DIR) .pytest_cache
	find $(wildcard addon scenes tests tools) -name __pycache__ -type d -prune -exec rm -rf {} +
