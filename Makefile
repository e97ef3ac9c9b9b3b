# The two commands (see README): `make demo` and `make test`. Both install what is missing first.
BUILD ?= build
JOBS ?= 2
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3
DEMO_CASE ?= examples/cases/maxilla-implants.json

.PHONY: all deps build install test format-check test-main test-sanitize test-fuzz test-setup demo examples bench bench-references clean

all: build

deps:
	@scripts/setup.sh

build: deps
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j$(JOBS)

# The workbench, its icons and the kernel module into FreeCAD's user Mod folder (FreeCAD 0.20 reads
# ~/.local/share/FreeCAD/Mod; FREECAD_USER_DATA moves it, as for FreeCAD itself).
FREECAD_MOD ?= $(if $(FREECAD_USER_DATA),$(FREECAD_USER_DATA),$(HOME)/.local/share/FreeCAD)/Mod
install: build
	rm -rf $(FREECAD_MOD)/SurgicalTemplate
	cmake --install $(BUILD) --prefix $(FREECAD_MOD) --component workbench
	@echo "Surgical Template installed in $(FREECAD_MOD)/SurgicalTemplate"

# Everything CI runs: the Release tests (GoogleTest, pytest), the kernel tests under ASan+UBSan, and
# each file-reader and case-parser fuzzer for a bounded time.
test: format-check test-main test-sanitize test-fuzz test-setup

# The C++ sources as clang-format (.clang-format) writes them; `make format` rewrites them so.
FORMATTED = $(shell git ls-files 'kernel/*.h' 'kernel/*.cpp' 'tests/*.h' 'tests/*.cpp' 'bench/*.h' 'bench/*.cpp' | grep -v /compat/)
format-check: deps
	@clang-format --dry-run --Werror $(FORMATTED) && echo "format-check: $(words $(FORMATTED)) files as clang-format writes them"

format: deps
	clang-format -i $(FORMATTED)

test-main: build
	ctest --test-dir $(BUILD) -j$(JOBS) --output-on-failure

test-sanitize: deps
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DST_SANITIZE=ON -DST_BUILD_PYTHON=OFF
	cmake --build build-asan -j$(JOBS) --target st_kernel_tests
	ST_PROPERTY_CASES=200 ctest --test-dir build-asan -j$(JOBS) --output-on-failure

test-fuzz: deps
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DST_FUZZ=ON \
	  -DCMAKE_AR=/usr/bin/ar -DCMAKE_RANLIB=/usr/bin/ranlib \
	  -DST_BUILD_TESTS=OFF -DST_BUILD_PYTHON=OFF \
	  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer"
	cmake --build build-fuzz -j$(JOBS) --target fuzz_stl fuzz_ply fuzz_obj fuzz_gz fuzz_case fuzz_plan
	ctest --test-dir build-fuzz -j$(JOBS) --output-on-failure -R fuzz_

# The set-up list is complete: every file under /usr that the three build trees and the Python code
# used comes from a package of scripts/packages.txt or one it depends on (and each listed package is
# needed). Last, after every build tree is built.
test-setup: deps
	ST_BUILD_DIRS="$(BUILD) build-asan build-fuzz" /usr/bin/python3 -m pytest -q tests/setup

# The demo: the tool designs the case; then the workbench (installed in a private FreeCAD user folder
# under out/, so your own FreeCAD is untouched) builds its parametric document and documentation:
# out/demo/<case>.stl, .FCStd, -drawing.pdf/.svg/.txt (the drawing runs FreeCAD's GUI under Xvfb).
DEMO_USER = $(CURDIR)/out/freecad-user
demo: build
	mkdir -p out
	$(BUILD)/surgical-template design $(DEMO_CASE) -o out/demo-template.stl --report out/demo-report.json
	$(BUILD)/surgical-template check out/demo-template.stl
	$(MAKE) --no-print-directory install FREECAD_MOD=$(DEMO_USER)/Mod
	FREECAD_USER_DATA=$(DEMO_USER) FREECAD_USER_HOME=$(DEMO_USER) ST_CASE=$(DEMO_CASE) ST_OUT=out/demo \
	  /usr/bin/python3 examples/macros/make_guide.py

# The paper's four surgical cases (examples/cases) designed with the tool, summarised like its Table 1.
examples: build
	/usr/bin/python3 examples/table1.py --build $(BUILD) --out out/examples

bench: build
	/usr/bin/python3 bench/run_bench.py --build $(BUILD)
	/usr/bin/python3 bench/run_validation_bench.py --build $(BUILD)
	/usr/bin/python3 bench/run_workbench_bench.py --build $(BUILD)

# The same benchmark with the off-the-shelf references side by side: the initial template with VTK +
# OpenVDB, the Boolean operation with CGAL's corefinement and VTK's two Boolean filters (all Debian).
bench-references: build
	@ST_EXTRA_PACKAGES="libvtk9-dev libopenvdb-dev libtbb-dev libboost-iostreams-dev libcgal-dev" scripts/setup.sh
	cmake -S . -B build-ref $(CMAKE_FLAGS) -DST_BENCH_REFERENCES=ON -DST_BUILD_TESTS=OFF
	cmake --build build-ref -j$(JOBS) --target reference-chain boolean-reference
	/usr/bin/python3 bench/run_bench.py --build $(BUILD) --reference build-ref/reference-chain \
	  --reference-boolean build-ref/boolean-reference --write

clean:
	rm -rf $(BUILD) build-asan build-fuzz out
