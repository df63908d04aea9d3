# Thin wrappers: every target calls a real tool. `make test` and `make demo`
# work on a fresh machine (they run the setup first).
PY := .venv/bin/python
# Python 3.13 with bpy 5.2: builds and tests the core for Blender 5.1 and later.
PY313 := .venvs/bpy-5.2/bin/python
# Python 3.10, as blender.org's Blender 3.4 to 4.0 embed it: the core is built and tested for it too.
PY310 := .venvs/py-3.10/bin/python
ENGINE_SOURCES := $(shell find engine -name '*.cpp' -o -name '*.h') CMakeLists.txt pyproject.toml
JOBS ?= $(shell nproc)
# The slowest tests of each run are listed, so that a CI log shows where the time goes.
PYTEST := -m pytest -q --durations=8

.PHONY: setup build demo demo-core test test-cpp test-cross test-python test-python-3.10 test-python-3.11 \
  test-python-3.13 bench bench-cpp lint clean

setup: .venv/.setup-done build

.venv/.setup-done: tools/setup.sh requirements.txt requirements-demo.txt
	tools/setup.sh
	touch $@

# The demo's share of the set-up: the compiler's packages, .venv with Blender 5.0 as the bpy module and
# the core for its Python 3.11 (no test environments, Blender binary or cross compiler).
.venv/.demo-setup-done: tools/setup.sh requirements-demo.txt
	tools/setup.sh --demo
	touch $@
build/.demo-core-installed: .venv/.demo-setup-done tools/build_cores.sh $(ENGINE_SOURCES)
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) tools/build_cores.sh --demo
	touch $@

# Build ppm_core (Release, -O3) for every Python Blender embeds, 3.10, 3.11 and 3.13, and install it into
# every virtual environment (tools/build_cores.sh).
build: build/.cores-installed
build/.cores-installed: .venv/.setup-done tools/build_cores.sh $(ENGINE_SOURCES)
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) tools/build_cores.sh
	touch $@

# Render the bundled Cornell box (report figure 1) to out/cornell_3spheres.{exr,png}.
# A bundled .blend rendered end to end through the add-on (Blender 5.0 as the bpy module).
demo: build/.demo-core-installed
	$(PY) render.py blend_scenes/cornell_3spheres.blend --output out/cornell_3spheres.png --time-limit 20

# The core alone, without Blender: the same scene built in Python and rendered through ppm_core.
demo-core: setup
	$(PY) blend_scenes/render_core_scene.py cornell_3spheres --output out/cornell_3spheres_core.exr --seconds 20

# The parts run two at a time (the machine's two cores), each part's output printed whole when it
# ends: the Blender versions' comparisons keep both cores busy, the other parts mostly one, so each
# fills the other's gaps. One part per Blender version and per Python, the longest listed first, so
# that the last to end is a short one (with test-blenders-full and test-python whole, one core
# idled for minutes at the end while the other finished a long part).
TEST_PARTS := test-blenders-5.0 test-python-3.11 test-blenders-3.4 test-addon-main \
  $(foreach v,5.2 4.5 4.2,test-blenders-$(v) test-addon-bpy-$(v)) test-python-3.10 test-python-3.13 test-cpp \
  test-blenders-zip
test: setup
	@start=$$(date +%s); $(MAKE) --no-print-directory -j 2 --output-sync=target $(TEST_PARTS) && \
	  echo "make test: the tests took $$(( $$(date +%s) - start )) s after the set-up"

# The engine's sources compile as for the cores (tools/build_cores.sh): ccache serves them from those builds.
CCACHE := $(if $(shell command -v ccache),-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
test-cpp: .venv/.setup-done
	cmake -S . -B build/tests -G Ninja -DPPM_BUILD_TESTS=ON -DPPM_BUILD_PYTHON=OFF -DCMAKE_BUILD_TYPE=Release $(CCACHE) >/dev/null
	CCACHE_BASEDIR="$(CURDIR)" CCACHE_NOHASHDIR=1 cmake --build build/tests -j $(JOBS)
	ctest --test-dir build/tests --output-on-failure -j $(JOBS)

# Linux aarch64, the one other platform this machine can run: the C++ tests cross-built with Debian's
# g++-aarch64-linux-gnu and run under qemu-user, the slowest statistical tests with a quarter of their
# samples (tests/core/random_test_helpers.h: test_samples); .ci/run runs it after make test.
test-cross: .venv/.setup-done
	cmake -S . -B build/aarch64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=tools/cross/aarch64-linux-gnu.cmake \
	  -DPPM_GTEST_SOURCE=/usr/src/googletest -DPPM_BUILD_TESTS=ON -DPPM_BUILD_PYTHON=OFF -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build/aarch64 -j $(JOBS)
	PPM_TEST_SAMPLE_DIVISOR=4 ctest --test-dir build/aarch64 --output-on-failure -j $(JOBS)

# The core's Python tests under every Python Blender embeds (3.13 also brings numpy 2, as Blender 5.2
# does; 3.10 is blender.org's Blender 3.4 to 4.0). Renders checked against answers (marker `accuracy`,
# pyproject.toml) check the C++ core's arithmetic, the same code under any Python: they run under 3.11 only.
# The memory of production sizes is the C++ core's too: it is measured under 3.11 only.
test-python: test-python-3.11 test-python-3.13 test-python-3.10
test-python-3.11: build
	$(PY) $(PYTEST) tests/core tests/bench tests/docs
test-python-3.13: build
	$(PY313) $(PYTEST) -m "not accuracy" --ignore=tests/core/test_production_sizes.py tests/core
test-python-3.10: build
	$(PY310) $(PYTEST) -m "not accuracy" --ignore=tests/core/test_production_sizes.py tests/core

# Benchmarks: figures and the commands behind them are in bench/README.md; every experiment is
# `$(PY) bench/run.py NAME` (bench/experiments/NAME.toml); these are the speed ones.
bench: setup bench-cpp .venv/.bench-deps
	build/bench/bezier_bench
	build/bench/grid_bench
	$(PY) bench/run.py throughput
	$(PY) bench/run.py raycast
	$(PY) bench/run.py skips

.venv/.bench-deps: bench/requirements.txt .venv/.setup-done
	$(PY) -m pip install -q -r bench/requirements.txt
	touch $@

bench-cpp: .venv/.setup-done
	cmake -S . -B build/bench -G Ninja -DPPM_BUILD_BENCH=ON -DPPM_BUILD_PYTHON=OFF -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build/bench -j $(JOBS)

# ruff, and the house's layers: engine/ folders include only those below them, the add-on has no import circle.
lint: .venv/.setup-done
	$(PY) -m ruff check .
	$(PY) tools/check_layers.py

clean:
	rm -rf build out

# The Blender add-on: the installable zip (with the cores for Python 3.11 and 3.13 inside)
# -> out/ppm_render-<version>-linux-x64.zip.
.PHONY: addon test-addon test-addon-main test-blenders test-blenders-full test-blenders-zip blend-scenes
addon: build
	$(PY) addon/build_addon.py --out out

# Add-on tests: bpy 5.0 (tests/addon), Debian's Blender 3.4 from a shell (tests/cli), the GUI under Xvfb
# (tests/gui), a still's shares on a dask LocalCluster (tests/farm), and the add-on's own tests again
# in bpy 4.2, 4.5 and 5.2.
test-addon: test-addon-main $(foreach v,4.2 4.5 5.2,test-addon-bpy-$(v))
test-addon-main: build
	$(PY) $(PYTEST) tests/addon tests/cli tests/gui tests/farm
test-addon-bpy-%: build
	.venvs/bpy-$*/bin/python $(PYTEST) tests/addon

# The zip in every Blender version against its Cycles (tests/blenders), a target per version
# (test-blenders-5.0 and so on): 3.4 and 5.0, checked case by case, are the longest parts of `make
# test`; 4.2, 4.5 and 5.2 (a subset); and the zip's other checks (test-blenders-zip).
IN_BLENDER := tests/blenders/test_blender_versions.py::test_zip_installs_renders_and_agrees_with_cycles
test-blenders-full: test-blenders-3.4 test-blenders-5.0
test-blenders: $(foreach v,4.2 4.5 5.2,test-blenders-$(v)) test-blenders-zip
test-blenders-zip: build
	$(PY) $(PYTEST) tests/blenders -k "not test_zip_installs_renders_and_agrees_with_cycles"
test-blenders-%: build
	$(PY) $(PYTEST) '$(IN_BLENDER)[$*]'

# Rebuild the bundled .blend files with Blender 3.4, so that both 3.4 and 5.0 open them.
blend-scenes: setup
	blender -b --factory-startup --python-exit-code 1 -P blend_scenes/build_blend_scenes.py
