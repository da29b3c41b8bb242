# sphcut - the two commands a user needs:
#   make example   builds what is missing (dependencies, plugin) and runs the first example
#   make test      builds what is missing and runs the test suite (ctest)
# Options: JOBS=N (parallel build jobs), SPHCUT_CACHE=dir (dependency cache, default ~/.cache/sphcut)

JOBS ?= $(shell nproc)
BUILD ?= build
DEPS_PREFIX := $(shell bash tools/build-deps.sh --print-prefix)

.PHONY: all deps build test example clean

all: build

deps:
	bash tools/build-deps.sh --jobs $(JOBS)
	bash tools/python-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -G Ninja -DSPHCUT_DEPS_FILE=$(DEPS_PREFIX)/sphcut-deps.cmake \
	  -DSPHCUT_PYTHON=$(shell bash tools/python-deps.sh --print-python)

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

example: build
	bash tools/run-example.sh $(BUILD)

clean:
	rm -rf $(BUILD)
