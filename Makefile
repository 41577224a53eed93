# Two entry points: `make render` and `make test`. Each installs what is missing, configures, builds.
BUILD ?= build
JOBS ?= $(shell nproc)
SCENE ?= scenes/cornell-box.gltf
RENDER_ARGS ?=

.PHONY: all deps configure build render test test-blender stress test-sanitize fuzz clean
all: build

deps:
	@bash tools/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# Only the CLI: a first picture does not wait for the test binary.
render: configure
	cmake --build $(BUILD) -j $(JOBS) --target dacrt-cli
	@mkdir -p out
	$(BUILD)/dacrt render $(SCENE) -o out/$(basename $(notdir $(SCENE))).exr \
	  --preview out/$(basename $(notdir $(SCENE))).png --stats out/$(basename $(notdir $(SCENE))).json $(RENDER_ARGS)

# The reports' tests need Chromium (headless) and HTML Tidy; nothing else does.
test: build
	@bash tools/install-deps.sh chromium tidy
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The Blender add-on's tests in headless Blender: Debian's blender is large, so only this target
# installs it (`make test` skips them with a message when it is missing). Configuring again
# lets CMake find the newly installed program.
test-blender: build
	@bash tools/install-deps.sh blender
	cmake -S . -B $(BUILD)
	cd $(BUILD) && ctest --output-on-failure -R blender

# The numerical stress suite in full: the short checks (also in `make test`), then the sweep of
# translation 10^k and scale 10^±k, which prints the largest level at which each check holds.
stress: build
	cd $(BUILD) && ./dacrt-tests -tc='stress:*' && ./dacrt-tests -ts=stress-sweep --no-skip

# AddressSanitizer + UndefinedBehaviorSanitizer build in its own directory. The three statistical
# end-to-end renders of the convergence suite (3.5 minutes of CPU there) and the default lighting
# of all 48 real scenes and the docs' examples run in `make test` only: the code they cover runs
# under the sanitizers in the shorter render and CLI tests (the loader over every real scene in
# gltf's and the Khronos tests).
SANITIZE_SKIP ?= convergence suite: (many low-spp|the Lambert lanes render|embree agrees)|default lighting: every scene of ../shared|docs: every example of README.md
test-sanitize: deps
	@bash tools/install-deps.sh chromium tidy
	cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDACRT_SANITIZE=ON
	cmake --build build-sanitize -j $(JOBS)
	cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS) -E '$(SANITIZE_SKIP)'

# libFuzzer on the glTF loader, on the EXR environment map reader and on the part file reader of
# `dacrt merge` and `render --resume` (clang), FUZZ_SECONDS each: 10 minutes in all by default.
# The corpora grow in build-fuzz/corpus (from scenes/, the kept findings in tests/fuzz/, the
# compressed-geometry seeds in fuzz/seeds-gltf/ and the optimisers' files in tests/published/),
# build-fuzz/corpus-exr (from the seeds in tests/fuzz-exr/) and build-fuzz/corpus-part (from the
# parts in tests/fuzz-part/); new findings land in fuzz/findings/: copy each into tests/fuzz/,
# tests/fuzz-exr/ or tests/fuzz-part/ (the suite loads them all under the sanitizers) once it is
# fixed.
FUZZ_SECONDS ?= 200
fuzz:
	@bash tools/install-deps.sh clang libclang-rt-14-dev
	CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDACRT_FUZZ=ON \
	  -DDACRT_TESTS=OFF -DDACRT_WITH_EMBREE=OFF
	cmake --build build-fuzz -j $(JOBS) --target gltf-fuzzer exr-fuzzer part-fuzzer
	@mkdir -p build-fuzz/corpus build-fuzz/corpus-exr build-fuzz/corpus-part fuzz/findings
	status=0; \
	build-fuzz/gltf-fuzzer -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 \
	  -dict=fuzz/gltf.dict -artifact_prefix=fuzz/findings/ build-fuzz/corpus scenes tests/fuzz \
	  fuzz/seeds-gltf tests/published || status=1; \
	build-fuzz/exr-fuzzer -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 \
	  -artifact_prefix=fuzz/findings/exr- build-fuzz/corpus-exr tests/fuzz-exr || status=1; \
	build-fuzz/part-fuzzer -max_total_time=$(FUZZ_SECONDS) -timeout=10 -rss_limit_mb=2048 \
	  -artifact_prefix=fuzz/findings/part- build-fuzz/corpus-part tests/fuzz-part || status=1; \
	exit $$status

clean:
	rm -rf $(BUILD) build-sanitize build-fuzz out
