# minibot3d: one-command set-up, tests, demo and benchmarks. See README.md and docs/getting_started.md.
# On a built tree `make demo` and `make test` start at once: deps only looks (no sudo) when
# nothing is missing, and build is a no-op when no source file changed.
SHELL := /bin/bash
# The system interpreter must come first: pyenv's python3 cannot see Debian's ROS modules.
export PATH := /usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:$(PATH)
JOBS ?= 2
# FORCE=1: run catkin_make even when no source file changed since the last build.
FORCE ?= 0
WORLD ?=
# make demo's robot: ROBOT=NAME a shipped one (config/robots/NAME); CONFIG=DIR a user's config set
# (its robot.yaml names the model and topics), MODEL=path/to/robot.xacro replacing that model.
ROBOT ?=
CONFIG ?=
MODEL ?=
BENCH_LOG ?= ../shared/datasets/intel/intel.clf
# The real logs SLAM is run on in make bench: 'NAME LOG [REFERENCE_LOG]' a line (missing ones skipped).
BENCH_LOGS ?= tools/bench/real_logs.txt

.PHONY: setup deps build install test demo bench clean

setup: deps build

deps:
	tools/install_deps.sh

build:
	JOBS=$(JOBS) FORCE=$(FORCE) tools/build.sh

# catkin's install space in install/ (source install/setup.bash to run from it). install/ is inside
# the source space: CATKIN_IGNORE keeps catkin and rospack from finding its packages a second time.
install: deps
	JOBS=$(JOBS) tools/build.sh install
	touch install/CATKIN_IGNORE

test: setup
	tools/run_tests.sh

demo: setup
	tools/demo.sh $(if $(ROBOT),--robot '$(ROBOT)') $(if $(CONFIG),--config '$(CONFIG)') \
	  $(if $(MODEL),--model '$(MODEL)') $(WORLD)

bench: setup
	BENCH_LOGS='$(BENCH_LOGS)' tools/bench.sh $(BENCH_LOG)

clean:
	rm -rf build devel install
