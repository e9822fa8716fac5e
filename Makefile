# The two README commands:
#   make demo   install what is missing, build, run the main job on the default scene
#   make test   install what is missing, build, run the whole test suite through CTest
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release -DPWSIM_WERROR=ON

.PHONY: demo test deps build bench clean

deps:
	./scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS)
	cmake --build $(BUILD_DIR) -j $(JOBS)

# demo builds only the pwsim command (tests and benchmarks are built by `make test` / `make bench`)
demo: deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target pwsim
	./$(BUILD_DIR)/pwsim run --out out/demo

test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) --timeout 300

bench: build
	./scripts/run-benchmarks.sh $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) out
