# dynamap — top-level wrapper around CMake.
#
#   make demo    install what is missing, build, map the bundled rawlog, say where the pictures are
#   make test    install what is missing, build, run every test (ctest)
#   make bench   install, build, time dynamap against plain MRPT grid insertion
#   make deps    only install the Debian packages below (when any is missing)
#   make build   only configure and build (Release) into build/
#   make format  apply .clang-format to every source file
#   make scenarios  regenerate every bundled rawlog and its ground truth from config/scenarios/
#   make eval    map every bundled scenario and score it against its ground truth beside the
#                paper's Table 3 (docs/evaluation.md)
#   make compare-icp-slam  odometry-only mapping: dynamap's scan matching against MRPT's icp-slam
#                and raw odometry on corridors_odom (installs mrpt-apps), and the SENA log maps

# Debian 12 packages the build, the tests and the demo need. MRPT's per-module -dev packages
# keep the install well below the whole libmrpt-dev metapackage.
DEB_PACKAGES := cmake g++ make \
  libmrpt-maps-dev libmrpt-obs-dev libmrpt-img-dev libmrpt-config-dev libmrpt-io-dev \
  libmrpt-serialization-dev libmrpt-poses-dev libmrpt-system-dev libmrpt-slam-dev \
  libeigen3-dev libboost-program-options-dev libgtest-dev

BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DYNAMAP := $(BUILD_DIR)/dynamap
DEMO_INPUT ?= rawlogs/people/people.rawlog
DEMO_OUT ?= out/people
# Real logs live beside the repository when they are there (never committed).
DATASETS ?= ../shared/datasets
FREIBURG := $(DATASETS)/carmen/freiburg-079-corrected.log.gz
BENCH_INPUT ?= $(if $(wildcard $(FREIBURG)),$(FREIBURG),rawlogs/corridors/corridors.rawlog)

.PHONY: all deps configure build test demo bench format clean scenarios eval compare-icp-slam

all: build

deps:
	@missing=""; \
	for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "dynamap: installing Debian packages:$$missing"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi

$(BUILD_DIR)/CMakeCache.txt:
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)

configure: deps $(BUILD_DIR)/CMakeCache.txt

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: build
	$(DYNAMAP) map --config config/default.ini --input $(DEMO_INPUT) --out $(DEMO_OUT)
	@echo "dynamap: done; pictures in $(DEMO_OUT)/: static.png (the static map S), dynamic.png (D), overlay.png"

bench: build
	@[ -f "$(FREIBURG)" ] || echo "dynamap: $(FREIBURG) not found, benchmarking the bundled corridors rawlog"
	$(BUILD_DIR)/dynamap_bench --input $(BENCH_INPUT) $(BENCH_ARGS)

# Each config/scenarios/<name>.ini writes rawlogs/<name>/<name>.{rawlog,gt.txt,objects.csv,
# moves.csv,world.png}; the SimBundled tests fail when the committed files are stale.
SCENARIOS := arena corridors corridors_odom people tiny
scenarios: build
	@for s in $(SCENARIOS); do \
	  $(DYNAMAP) simulate --scenario config/scenarios/$$s.ini --out rawlogs/$$s || exit 1; \
	done

# Each scenario is mapped with ground-truth poses into out/<name>/ and evaluated there
# (report.md, metrics.json); then one table of all of them beside the paper's. The scenarios of
# SCAN_MATCHING_SCENARIOS are mapped from their odometry corrected by scan matching instead.
EVAL_SCENARIOS := arena corridors corridors_odom people
SCAN_MATCHING_SCENARIOS := corridors_odom
eval: build
	@for s in $(EVAL_SCENARIOS); do \
	  poses=ground_truth; \
	  case " $(SCAN_MATCHING_SCENARIOS) " in *" $$s "*) poses=scan_matching;; esac; \
	  $(DYNAMAP) map --config config/default.ini --poses $$poses \
	    --input rawlogs/$$s/$$s.rawlog --out out/$$s || exit 1; \
	  $(DYNAMAP) eval --scenario config/scenarios/$$s.ini --truth rawlogs/$$s/$$s \
	    --result out/$$s || exit 1; \
	  echo; \
	done
	@$(DYNAMAP) eval --summary $(addprefix out/,$(EVAL_SCENARIOS))

# Odometry-only mapping, side by side on corridors_odom: dynamap with ground-truth poses, with
# scan matching and with raw odometry, and MRPT's icp-slam (config/icp_slam.ini, adapted from
# MRPT's demo), each scored by `dynamap eval --trajectory` (absolute trajectory error). Then
# MRPT's odometry-only SENA log mapped with odometry and with scan matching. Installs mrpt-apps
# (icp-slam) and mrpt-common (the SENA log) when missing; `make test` needs neither.
COMPARE_SCENARIO := corridors_odom
COMPARE_OUT := out/compare# also logOutput_dir in config/icp_slam.ini
SENA_LOG := /usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog
compare-icp-slam: build
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="mrpt-apps mrpt-common"
	@mkdir -p $(COMPARE_OUT)
	@s=$(COMPARE_SCENARIO); log=rawlogs/$$s/$$s.rawlog; \
	for p in ground_truth scan_matching odometry; do \
	  $(DYNAMAP) map --config config/default.ini --poses $$p --input $$log \
	    --out $(COMPARE_OUT)/$$s-$$p || exit 1; \
	done; \
	echo "dynamap: running icp-slam on $$log (log in $(COMPARE_OUT)/icp-slam.log)"; \
	icp-slam config/icp_slam.ini $$log < /dev/null > $(COMPARE_OUT)/icp-slam.log 2>&1 || exit 1; \
	awk 'NR == FNR { if ($$0 !~ /^[%#]/) t[n++] = $$1; next } \
	     ($$1 % 3) == 1 { print t[($$1 - 1) / 3], $$2, $$3, $$4 }' \
	  rawlogs/$$s/$$s.gt.txt $(COMPARE_OUT)/icp_slam/log_estimated_path.txt \
	  > $(COMPARE_OUT)/icp_slam/poses.txt; \
	echo; for r in $$s-scan_matching/poses.txt icp_slam/poses.txt $$s-odometry/poses.txt; do \
	  $(DYNAMAP) eval --truth rawlogs/$$s --trajectory $(COMPARE_OUT)/$$r || exit 1; \
	done; \
	for p in ground_truth scan_matching; do echo; \
	  $(DYNAMAP) eval --scenario config/scenarios/$$s.ini --truth rawlogs/$$s \
	    --result $(COMPARE_OUT)/$$s-$$p | head -8 || exit 1; \
	done
	@for p in odometry scan_matching; do \
	  $(DYNAMAP) map --config config/default.ini --poses $$p --input "$(SENA_LOG)" \
	    --out $(COMPARE_OUT)/sena-$$p || exit 1; \
	done; echo "dynamap: SENA maps in $(COMPARE_OUT)/sena-odometry/ and sena-scan_matching/"

format:
	clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	rm -rf $(BUILD_DIR) out
