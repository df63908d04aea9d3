# Thin wrappers: every target calls a real tool. `make test` and `make demo`
# work on a fresh machine (they run the setup first).
PY := .venv/bin/python
ENGINE_SOURCES := $(shell find engine -name '*.cpp' -o -name '*.h') CMakeLists.txt pyproject.toml
JOBS ?= $(shell nproc)

.PHONY: setup build demo test test-cpp test-python bench lint clean

setup: .venv/.setup-done build

.venv/.setup-done: tools/setup.sh requirements.txt
	tools/setup.sh
	touch $@

# Build and install ppm_core into the virtual environment (Release, -O3).
build: .venv/.ppm_core-installed
.venv/.ppm_core-installed: .venv/.setup-done $(ENGINE_SOURCES)
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PY) -m pip install -q --no-build-isolation .
	touch $@

# Render the bundled Cornell box (report figure 1) to out/cornell_3spheres.{exr,png}.
demo: setup
	$(PY) blend_scenes/render_core_scene.py cornell_3spheres --output out/cornell_3spheres.exr --seconds 20

test: setup test-cpp test-python

test-cpp: .venv/.setup-done
	cmake -S . -B build/tests -G Ninja -DPPM_BUILD_TESTS=ON -DPPM_BUILD_PYTHON=OFF -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build build/tests -j $(JOBS)
	ctest --test-dir build/tests --output-on-failure -j $(JOBS)

test-python: build
	$(PY) -m pytest -q tests/core

bench: setup
	$(PY) bench/throughput.py

lint:
	$(PY) -m ruff check . || true

clean:
	rm -rf build out
