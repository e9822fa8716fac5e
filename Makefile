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

# test ends with the ten slowest tests of this run (from CTest's log), whether it passed or not
test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS) --timeout 300; status=$$?; \
	echo "The ten slowest tests of this run:"; \
	awk '/^[0-9]+\/[0-9]+ Test: /{name=$$3} /^Test time =/{print $$4, name}' \
	    $(BUILD_DIR)/Testing/Temporary/LastTest.log | sort -rn | head -10 | \
	    awk '{printf "  %7.1f s  %s\n", $$1, $$2}'; \
	exit $$status

bench: build
	./scripts/run-benchmarks.sh $(BUILD_DIR)

clean:
	rm -rf $(BUILD_DIR) out
