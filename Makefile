# cam_ros: every target runs in the project's own virtual environment (.venv), made by `make setup`.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
CMAKE := $(VENV)/bin/cmake
IFACE_BUILD := $(VENV)/build/cam_ros_interfaces
CONFIG ?= config/default.yaml
PYTEST_ARGS ?=

.PHONY: setup run test lint bench docs lock clean mutate

# Only when there is something to build: check the system first (tools/preflight.sh, with the
# venv's Python once there is one), so a missing tool stops the set-up within seconds, before the
# venv is made or anything is downloaded. The studio's browser tests drive Debian's chromium
# (Playwright cannot download its own here): installed when missing and the user is root with
# apt-get, as .ci/run does; otherwise set-up says so and those tests say why they skip.
CHROMIUM := /usr/bin/chromium
setup:
	@$(MAKE) --no-print-directory --question $(VENV)/.cam_ros.stamp || { sh tools/preflight.sh \
	  $(or $(wildcard $(PY)),$(PYTHON)) && $(MAKE) --no-print-directory $(VENV)/.cam_ros.stamp; }
	@[ -x $(CHROMIUM) ] || { [ "$$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1 && \
	  apt-get update -qq && apt-get install -y -qq chromium >/dev/null; } || \
	  echo "make setup: no $(CHROMIUM): the studio's browser tests skip (apt-get install chromium)" >&2

$(PY):
	$(PYTHON) -m venv $(VENV)

$(VENV)/.deps.stamp: requirements.lock | $(PY)
	$(PY) -m pip install --quiet -r requirements.lock
	touch $@

# The interface package is a real ament_cmake package, built straight into the venv with the venv's
# CMake (the cmake wheel in requirements.lock), so no system CMake is needed.
$(VENV)/.interfaces.stamp: $(VENV)/.deps.stamp $(wildcard cam_ros_interfaces/*.* cam_ros_interfaces/msg/* cam_ros_interfaces/srv/*)
	rm -rf $(IFACE_BUILD) && mkdir -p $(IFACE_BUILD)
	prefix=$$(cd $(VENV) && pwd); export PATH="$$prefix/bin:$$PATH" AMENT_PREFIX_PATH="$$prefix"; \
	$(CMAKE) -S cam_ros_interfaces -B $(IFACE_BUILD) -DCMAKE_PREFIX_PATH="$$prefix" \
	  -DCMAKE_INSTALL_PREFIX="$$prefix" -DPython3_EXECUTABLE="$$prefix/bin/python" \
	  -DBUILD_TESTING=OFF > $(IFACE_BUILD).configure.log 2>&1 \
	  || { cat $(IFACE_BUILD).configure.log; exit 1; }
	$(CMAKE) --build $(IFACE_BUILD) -j2 > $(IFACE_BUILD).build.log 2>&1 \
	  || { tail -50 $(IFACE_BUILD).build.log; exit 1; }
	$(CMAKE) --install $(IFACE_BUILD) > /dev/null
	touch $@

# setup.cfg puts the executables in lib/cam_ros, where `ros2 run` looks; link them into bin too.
$(VENV)/.cam_ros.stamp: $(VENV)/.interfaces.stamp setup.py setup.cfg package.xml $(wildcard config/*.yaml)
	$(PY) -m pip install --quiet --no-deps --no-build-isolation -e .
	ln -sf ../lib/cam_ros/cam_node ../lib/cam_ros/cam_ros $(VENV)/bin/
	touch $@

run: setup
	$(VENV)/bin/cam_node --ros-args --params-file $(CONFIG)

test: setup
	$(PY) -m pytest $(PYTEST_ARGS)

bench: setup
	$(PY) -m benchmarks

# Mutation testing (mutmut, configured in setup.cfg [mutmut]): not part of `make test`. A clean
# run each time (mutmut copies the project into mutants/). MUTANTS picks the mutants by name: by
# default every one numbered ...0 or ...5 (one in five, as docs/reliability.md reports);
# MUTANTS='*' runs all of them (hours on two cores).
MUTANTS ?= cam_ros.core.*__mutmut_*[05]
mutate: setup
	rm -rf mutants
	nice -n 15 $(VENV)/bin/mutmut run --max-children 2 '$(MUTANTS)'
	$(VENV)/bin/mutmut results

# The documentation site (docs/: Sphinx with MyST Markdown, as rosdoc2 builds it); warnings are
# errors. `make test` builds it too (test/docs/test_build.py).
docs: setup
	$(PY) -m sphinx -W --keep-going -q -E -b html docs docs/_build/html

# Pins every distribution pip installed (egg-info folders that ROS wheels embed are not distributions).
lock: | $(PY)
	{ sed -n '1,2p' requirements.lock; $(PY) -c "$$LOCK_PY"; } > requirements.lock.new
	mv requirements.lock.new requirements.lock

define LOCK_PY
import importlib.metadata as md
pins = {f"{d.metadata['Name']}=={d.version}" for d in md.distributions()
        if d.read_text('INSTALLER') and d.read_text('direct_url.json') is None
        and d.metadata['Name'] != 'pip'}
print('\n'.join(sorted(pins, key=str.lower)))
endef
export LOCK_PY

clean:
	rm -rf $(VENV) build install log .pytest_cache .mypy_cache docs/_build
