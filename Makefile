# minibot3d — one-command set-up, tests, demo and benchmarks. See README.md.
SHELL := /bin/bash
# The system interpreter must come first: pyenv's python3 cannot see Debian's ROS modules.
export PATH := /usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
JOBS ?= 2
WORLD ?=
BENCH_LOG ?= ../shared/datasets/intel/intel.clf

.PHONY: setup deps build install test demo bench clean

setup: deps build

deps:
	tools/install_deps.sh

build:
	JOBS=$(JOBS) tools/build.sh

# catkin's install space in install/ (source install/setup.bash to run from it). install/ is inside
# the source space: CATKIN_IGNORE keeps catkin and rospack from finding its packages a second time.
install: deps
	JOBS=$(JOBS) tools/build.sh install
	touch install/CATKIN_IGNORE

test: setup
	tools/run_tests.sh

demo: setup
	tools/demo.sh $(WORLD)

bench: setup
	tools/bench.sh $(BENCH_LOG)

clean:
	rm -rf build devel install
