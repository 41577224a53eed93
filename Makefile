# Two entry points: `make render` and `make test`. Each installs what is missing, configures, builds.
BUILD ?= build
JOBS ?= $(shell nproc)
SCENE ?= scenes/cornell-box.gltf
RENDER_ARGS ?=

.PHONY: all deps configure build render test test-sanitize clean
all: build

deps:
	@bash tools/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

render: build
	@mkdir -p out
	$(BUILD)/dacrt render $(SCENE) -o out/$(basename $(notdir $(SCENE))).exr \
	  --preview out/$(basename $(notdir $(SCENE))).png --stats out/$(basename $(notdir $(SCENE))).json $(RENDER_ARGS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# AddressSanitizer + UndefinedBehaviorSanitizer build in its own directory.
test-sanitize: deps
	cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDACRT_SANITIZE=ON
	cmake --build build-sanitize -j $(JOBS)
	cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) build-sanitize out
