# ltm: the two entry points. Both install missing Debian packages, build (Release, Ninja, -j2)
# and run. Variables: BUILD (build dir), JOBS (parallel jobs), LTM_WITH_TORCH (ON/OFF).
BUILD ?= build
JOBS ?= 2
LTM_WITH_TORCH ?= ON
CMAKE_FLAGS ?=

.PHONY: all deps configure build test test-all demo bench viewer clean

all: build

deps:
	@LTM_WITH_TORCH=$(LTM_WITH_TORCH) scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DLTM_WITH_TORCH=$(LTM_WITH_TORCH) $(CMAKE_FLAGS) >/dev/null

build: configure
	@cmake --build $(BUILD) -j$(JOBS)

# Unit and slow tests; GPU-labelled tests are excluded (they skip cleanly without a GPU anyway).
test: build
	@ctest --test-dir $(BUILD) -LE gpu --output-on-failure -j$(JOBS)

demo: build
	@BUILD=$(BUILD) scripts/demo.sh

bench: build
	@BUILD=$(BUILD) scripts/bench.sh

# The browser viewer's bundle (web/dist/viewer.js: three.js from npm, esbuild); scripts/view.sh uses it.
viewer:
	@cd web && { [ -d node_modules/three ] || npm ci --no-audit --no-fund --loglevel=error; } && npm run -s build

clean:
	@rm -rf $(BUILD) demo-out
