# The two set-up commands of the README: `make run` and `make test`. Both install whatever
# Debian packages are missing, configure with CMake and build.
SHELL := /bin/bash
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
GENERATOR := $(shell command -v ninja >/dev/null 2>&1 && echo "-G Ninja")

# Debian packages the project builds with (see README "Dependencies").
DEB_PACKAGES := cmake g++ make ninja-build pkg-config \
  libeigen3-dev libboost1.81-dev nlohmann-json3-dev libsqlite3-dev \
  libgtest-dev libgmock-dev libbenchmark-dev libssl-dev libpq-dev libassimp-dev libzstd-dev \
  python3
# Only the tests need these: chromium for the browser tests, postgresql (15 on Debian 12) for the
# PostgreSQL store's tests, which start their own server in a temporary folder, curl and jq for
# the blocks of docs/pipelines.md (tests/docs/run_doc_blocks.py).
TEST_DEB_PACKAGES := chromium postgresql curl jq
# Only the deploy/ checks need these (tests/deploy.cmake): systemd-analyze, strace, shellcheck.
DEPLOY_TEST_DEB_PACKAGES := systemd strace shellcheck
# Only the fuzz targets need these (tests/fuzz): Debian 12's clang 14 and its compiler-rt, which
# has libFuzzer and the sanitizer runtimes.
FUZZ_DEB_PACKAGES := clang libclang-rt-14-dev
# Benches only (issue 13): libccd for make narrowphase-bench (the narrowphase against libccd),
# Bullet for the side-by-side brick wall in step_bench (make bench). The product links neither;
# bench/CMakeLists.txt builds each comparison only where its package is installed, and make
# narrowphase-bench installs both.
BENCH_DEB_PACKAGES := libccd-dev libbullet-dev
# Seconds `make fuzz` runs each fuzz target.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := fuzz_scene fuzz_http fuzz_writers fuzz_fracture

.PHONY: all deps node gltf-validator web web-test-deps deploy-test-deps fuzz-deps fuzz-build fuzz soak build run test sanitize bench-deps bench contact-goals narrowphase-bench load-bench load-bench-postgres accuracy-study format clean

all: build

# $(call apt_install,PACKAGES): installs those of the Debian PACKAGES that are missing,
# non-interactively (as root, or through sudo).
define apt_install
	@missing=""; \
	for p in $(1); do \
	  dpkg-query -W -f='$${Status}' "$$p" 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "Installing missing Debian packages:$$missing"; \
	  sudo=""; [ "$$(id -u)" -eq 0 ] || sudo="sudo"; \
	  $$sudo apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq --no-install-recommends $$missing; \
	fi
endef

deps:
	$(call apt_install,$(DEB_PACKAGES))

# node and npm for the dashboard and the node-based tests: Debian's nodejs and npm only when no
# node is installed (a NodeSource node ships its own npm, which Debian's npm package conflicts
# with).
node:
	@if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then \
	  echo "Installing Debian packages nodejs npm"; \
	  sudo=""; [ "$$(id -u)" -eq 0 ] || sudo="sudo"; \
	  $$sudo apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $$sudo apt-get install -y -qq --no-install-recommends nodejs npm; \
	fi

# The Khronos glTF validator and three.js (tests/io.cmake), and the API contract tools
# (tests/contract.cmake), pinned in their package-lock.json files.
gltf-validator: node
	npm ci --prefix tests/gltf --no-audit --no-fund --loglevel=error
	npm ci --prefix tests/contract --no-audit --no-fund --loglevel=error

# The dashboard, built into web/dist (served by `brisance serve` at /). Each step runs only when
# its inputs changed: npm ci when a package-lock.json is newer than the packages it installed
# (a stamp in node_modules), the Vite build when a source is newer than web/dist.
WEB_SOURCES := $(shell find web/src clients/typescript/src -type f 2>/dev/null) web/index.html \
  web/vite.config.ts web/tsconfig.json
web: web/dist/index.html

%/node_modules/.brisance-installed: %/package-lock.json %/package.json | node
	npm ci --prefix $* --no-audit --no-fund --loglevel=error
	touch $@

web/dist/index.html: web/node_modules/.brisance-installed \
    clients/typescript/node_modules/.brisance-installed $(WEB_SOURCES)
	npm run --prefix web build
	touch $@

# The browser tests (tests/web.cmake): Debian's chromium driven by playwright-core; and the
# PostgreSQL server the store's tests start (tests/server/postgres_fixture.hpp).
web-test-deps: node
	$(call apt_install,$(TEST_DEB_PACKAGES))
	npm ci --prefix tests/web --no-audit --no-fund --loglevel=error

# The deploy/ checks (tests/deploy.cmake): systemd-analyze, strace, shellcheck, and the Kubernetes
# and Compose schema tools pinned in tests/deploy/package-lock.json.
deploy-test-deps: node
	$(call apt_install,$(DEPLOY_TEST_DEB_PACKAGES))
	npm ci --prefix tests/deploy --no-audit --no-fund --loglevel=error

# The libFuzzer targets (tests/fuzz): a build of their own with clang, -O1 with asserts on.
fuzz-deps:
	$(call apt_install,$(FUZZ_DEB_PACKAGES))

fuzz-build: deps fuzz-deps
	CC=clang CXX=clang++ cmake -S . -B $(BUILD_DIR)/fuzz $(GENERATOR) -DBRISANCE_FUZZ=ON \
	  -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g"
	cmake --build $(BUILD_DIR)/fuzz -j $(JOBS) --target fuzz_targets

# Runs each fuzz target for FUZZ_SECONDS from its committed seeds (tests/fuzz/corpus/TARGET);
# new inputs and crash reproducers go to $(BUILD_DIR)/fuzz/runs/TARGET.
fuzz: fuzz-build
	@for t in $(FUZZ_TARGETS); do \
	  echo "== $$t for $(FUZZ_SECONDS) s"; \
	  tests/fuzz/run_fuzz.sh $(BUILD_DIR)/fuzz/tests/fuzz/$$t $(BUILD_DIR)/fuzz/runs/$$t \
	    tests/fuzz/corpus/$$t $(FUZZ_SECONDS) || exit 1; \
	done

# The crash soak: kill -9 20 times and SIGTERM 5 times under load, per SQLite sync mode, on the
# release binary; the figures go to bench/results/soak.txt.
soak: build gltf-validator
	@{ echo "# make soak: python3 tests/soak/soak.py --brisance $(BUILD_DIR)/release/cli/brisance" \
	    "--validator tests/gltf/validate.mjs"; \
	  echo "# $$(date -u +%Y-%m-%d) on $$(nproc) cores, $$(git rev-parse --short HEAD)"; } \
	  > bench/results/soak.txt
	python3 tests/soak/soak.py --brisance $(BUILD_DIR)/release/cli/brisance \
	  --validator tests/gltf/validate.mjs | tee -a bench/results/soak.txt

$(BUILD_DIR)/release/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_DIR)/release $(GENERATOR) -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD_DIR)/release/CMakeCache.txt
	cmake --build $(BUILD_DIR)/release -j $(JOBS)

# Builds the release binary and serves the dashboard and the API on http://127.0.0.1:8080 with
# its SQLite store in ./data (Ctrl-C stops it gracefully). BRISANCE_* variables configure it
# (docs/service.md): no flag is passed, so none overrides them.
run: build web
	$(BUILD_DIR)/release/cli/brisance serve

# The whole test suite, built with AddressSanitizer + UndefinedBehaviorSanitizer and warnings as
# errors, run through CTest; then each fuzz target for a short bounded run (tests/fuzz).
test: deps gltf-validator web web-test-deps deploy-test-deps fuzz-build
	cmake -S . -B $(BUILD_DIR)/sanitize $(GENERATOR) -DCMAKE_BUILD_TYPE=Sanitize -DBRISANCE_WERROR=ON
	cmake --build $(BUILD_DIR)/sanitize -j $(JOBS)
	cd $(BUILD_DIR)/sanitize && ctest --output-on-failure -j $(JOBS)
	cd $(BUILD_DIR)/fuzz && ctest --output-on-failure

# Benchmarks need an optimised build, and step_bench's Bullet side by side needs Bullet (bench
# packages; the configure step looks for them again once they are installed).
bench-deps: build
	$(call apt_install,$(BENCH_DEB_PACKAGES))
	cmake -S . -B $(BUILD_DIR)/release -U__pkg_config_checked_CCD -U__pkg_config_checked_BULLET
	cmake --build $(BUILD_DIR)/release -j $(JOBS)

bench: bench-deps
	$(BUILD_DIR)/release/bench/blast_bench
	$(BUILD_DIR)/release/bench/step_bench
	$(BUILD_DIR)/release/bench/fracture_bench
	$(BUILD_DIR)/release/bench/occlusion_bench
	$(BUILD_DIR)/release/bench/response_bench
	$(BUILD_DIR)/release/bench/facade_bench

# Issue 13's speed goals (contacts between bodies), judged from one step_bench invocation:
# ratios against Bullet and against the runs without contacts, medians of 3.
contact-goals: bench-deps
	python3 bench/sim/contact_goals.py --step-bench $(BUILD_DIR)/release/bench/step_bench

# The narrowphase against libccd's GJK/EPA and MPR on the same box pairs
# (bench/results/narrowphase.txt).
narrowphase-bench: bench-deps
	$(BUILD_DIR)/release/bench/narrowphase_bench

# The job service under load: POST, GET, fixed-rate and drain phases against a spawned server.
load-bench: build
	$(BUILD_DIR)/release/bench/load_bench --server $(BUILD_DIR)/release/cli/brisance

# The same bench on PostgreSQL (a durable server of its own) with 1 and 3 nodes;
# bench/results/load_postgres.txt holds a run.
load-bench-postgres: build
	bench/load/postgres_bench.sh $(BUILD_DIR)/release

# Run time versus error of integrators, steps and panel sizes on the example scenes; writes
# bench/results/accuracy_study.{csv,svg,txt} (docs/simulator.md reads the defaults off it).
accuracy-study: build
	$(BUILD_DIR)/release/bench/accuracy_study --scenes scenes --out bench/results | tee bench/results/accuracy_study.txt

format:
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) web/dist
