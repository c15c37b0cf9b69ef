# dynamap — top-level wrapper around CMake.
#
#   make demo    install what is missing, build a dynamap with map and config only into
#                build-demo/, map the bundled rawlog, say where the pictures are
#   make test    install what is missing, build, run every test (ctest; the Python module's
#                pytest files among them)
#   make bench   install, build, time dynamap against plain MRPT grid insertion, then the fixed
#                cost of a run, the whole odometry-only (slam) run, and a fleet of 16 logs
#                mapped one after another and as a batch on two local Dask workers
#   make deps    only install the Debian packages below (when any is missing)
#   make build   only configure and build (Release) into build/
#   make format  apply .clang-format to every source file
#   make scenarios  regenerate every bundled rawlog and its ground truth from config/scenarios/
#   make eval    map every bundled scenario and score it against its ground truth beside the
#                paper's Table 3 (docs/evaluation.md)
#   make eval-heldout  the same for the held-out worlds of config/heldout/ (simulated into
#                out/heldout/ first): worlds written to check the defaults, never to set them
#   make eval-real  the same on real scans: cylinders added to the Radish CARMEN logs of
#                $(DATASETS)/carmen/ when present (dynamap perturb --add-objects), 3 seeds each
#   make test-asan  build into build-asan/ with AddressSanitizer + UndefinedBehaviorSanitizer and
#                run every test there
#   make fuzz    install clang, build the libFuzzer targets into build-fuzz/ and run each for
#                FUZZ_SECONDS (60) seconds; new crashing inputs are left in build-fuzz/crashes/
#   make bench-long  memory and speed of one run over 100,000+ simulated scans, then the same
#                in a world of four times the area
#   make legs    regrow the people detector's leg classifier (config/legs.yml.gz) from the
#                leg training bags of $(DATASETS)/people/leg_training/
#   make eval-people  CLEAR MOT on the annotated person-following bag, and the object table of a
#                standing robot with people walking past ($(DATASETS)/people/)
#   make eval-slam  --poses slam on the real CARMEN logs of $(DATASETS)/carmen/ made to drift
#                (dynamap perturb, seeds 1-6; seed 0: no drift): one table of every log x seed
#                (bench/eval_slam.sh)
#   make eval-sessions  the simulated multi-session worlds of config/sessions/ scored by eval
#                --sessions (bench/eval_sessions_sim.sh); the same real logs cut in two sessions,
#                the second mapped against the first (--prior): the changes it reports and its
#                cost (bench/eval_sessions.sh)
#   make compare-icp-slam  odometry-only mapping: dynamap's scan matching against MRPT's icp-slam
#                and raw odometry on corridors_odom (installs mrpt-apps), and the SENA log maps
#                with odometry, scan matching and slam, each scored by its consistency

# ROS 1's rosbag and the messages dynamap reads from a bag (a build with -DDYNAMAP_ROSBAG=OFF
# needs none of them). Debian's rosbag headers include the ROS 2 pluginlib, hence the next five;
# ROS 2 bags (MCAP, .db3) take the last four: Fast-CDR, zstd and LZ4 chunks, SQLite.
ROSBAG_PACKAGES := librosbag-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev \
  libgeometry-msgs-dev pluginlib-dev libclass-loader-dev librcpputils-dev librcutils-dev \
  libament-index-cpp-dev libfastcdr-dev libzstd-dev liblz4-dev libsqlite3-dev

# Debian 12 packages the build, the tests and the demo need. MRPT's per-module -dev packages
# keep the install well below the whole libmrpt-dev metapackage. CORE_PACKAGES are what the
# dynamap program needs (all `make demo` installs); TEST_PACKAGES the tests': GoogleTest,
# mrpt-common (MRPT's own example logs, which the tests read: Malaga's simplemap) and ffmpeg
# (--frames-every frames into timelapse.mp4; its test needs it); PYTHON_PACKAGES the Python
# module (python/, built when pybind11 is installed), its tests (pytest, pandas) and the fleet
# batch (Dask).
PYTHON_PACKAGES := pybind11-dev python3-numpy python3-pytest python3-distributed python3-pandas
TEST_PACKAGES := libgtest-dev mrpt-common ffmpeg
CORE_PACKAGES := cmake g++ make \
  libmrpt-maps-dev libmrpt-obs-dev libmrpt-img-dev libmrpt-config-dev libmrpt-io-dev \
  libmrpt-serialization-dev libmrpt-poses-dev libmrpt-system-dev libmrpt-slam-dev \
  libmrpt-graphslam-dev \
  libeigen3-dev libboost-program-options-dev zlib1g-dev nlohmann-json3-dev \
  libopencv-ml-dev $(ROSBAG_PACKAGES)
DEB_PACKAGES := $(CORE_PACKAGES) $(TEST_PACKAGES) $(PYTHON_PACKAGES)

BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
DYNAMAP := $(BUILD_DIR)/dynamap
DEMO_INPUT ?= rawlogs/people/people.rawlog
DEMO_OUT ?= out/people
# Real logs (never committed): the Radish CARMEN logs under $(DATASETS)/carmen/ when present,
# e.g. make bench DATASETS=/data/logs.
DATASETS ?= datasets
FREIBURG := $(DATASETS)/carmen/freiburg-079-corrected.log.gz
BENCH_INPUT ?= $(if $(wildcard $(FREIBURG)),$(FREIBURG),rawlogs/corridors/corridors.rawlog)
# The odometry-only pipeline (--poses slam) is timed on Freiburg made to drift, or the bundled
# corridors_odom's ground truth made to drift.
SLAM_BENCH_INPUT ?= $(if $(wildcard $(FREIBURG)),$(FREIBURG),rawlogs/corridors_odom/corridors_odom.rawlog)

.PHONY: legs eval-people all deps configure build test demo bench format clean scenarios eval eval-heldout eval-real test-asan fuzz \
  fuzz-deps bench-long compare-icp-slam eval-slam eval-sessions

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

# The generated Makefile, not CMakeCache.txt, marks a finished configure: a configure that failed
# (say, before the packages were installed) leaves a cache behind and is run again.
$(BUILD_DIR)/Makefile:
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)

configure: deps $(BUILD_DIR)/Makefile

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Configured again first: a build configured before pybind11 was installed gains the Python
# module and its tests.
test: configure
	cmake -S . -B $(BUILD_DIR) > /dev/null
	cmake --build $(BUILD_DIR) -j $(JOBS)
	cd $(BUILD_DIR) && ctest --output-on-failure --no-tests=error -j $(JOBS)

# Only what the demo runs, in its own build directory (build-demo/): the dynamap program with
# `map` and `config` (-DDYNAMAP_DEMO=ON: no ROS bags, tests, benchmarks or Python module, which
# take most of a full build), and only the packages that program needs. make build and make test
# build the whole program into build/.
DEMO_DIR ?= build-demo
DEMO_PACKAGES := $(filter-out $(ROSBAG_PACKAGES),$(CORE_PACKAGES))
demo:
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="$(DEMO_PACKAGES)"
	cmake -S . -B $(DEMO_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DDYNAMAP_DEMO=ON > /dev/null
	cmake --build $(DEMO_DIR) -j $(JOBS) --target dynamap
	$(DEMO_DIR)/dynamap map --config config/default.ini --input $(DEMO_INPUT) --out $(DEMO_OUT)
	@echo "dynamap: done; pictures in $(DEMO_OUT)/: static.png (the static map S), dynamic.png (D), overlay.png"
	@echo "dynamap: $(DEMO_DIR)/dynamap has map and config only; make build builds every command into $(BUILD_DIR)/"

# The readers timed after the insertion figures: one log of each format at hand. Last, the fixed
# cost of a run (the bundled tiny log) beside a process that only loads MRPT's grid library.
MALAGA := /usr/share/mrpt/datasets/malaga-cs-fac-building.simplemap.gz
BENCH_READS ?= $(BENCH_INPUT) rawlogs/people/people.rawlog $(wildcard $(MALAGA)) \
  fuzz/seeds/bag/small.bag

# The bench log is read once more as a ROS 2 bag (MCAP, zstd chunks) that export-bag writes.
BENCH_MCAP := $(BUILD_DIR)/bench-input.mcap

# The fleet batch (bench/bench_batch.py): BENCH_BATCH_LOGS copies of bundled logs mapped one after
# another, then on a local Dask cluster of two worker processes.
BENCH_BATCH_LOGS ?= 16
PYTHON := /usr/bin/python3
bench: build
	@[ -f "$(FREIBURG)" ] || echo "dynamap: $(FREIBURG) not found, benchmarking the bundled corridors rawlog"
	$(DYNAMAP) export-bag $(BENCH_INPUT) --out $(BENCH_MCAP) --compression zstd > /dev/null
	$(BUILD_DIR)/dynamap_bench --input $(BENCH_INPUT) $(BENCH_ARGS) $(addprefix --read ,$(BENCH_READS)) \
	  --read $(BENCH_MCAP)
	@[ ! -f "$(MALAGA)" ] || $(BUILD_DIR)/dynamap_bench --input $(MALAGA) $(BENCH_ARGS)
	$(BUILD_DIR)/dynamap_bench_startup --dynamap $(DYNAMAP) --input rawlogs/tiny/tiny.rawlog \
	  --config config/default.ini
	$(BUILD_DIR)/dynamap_bench_slam --dynamap $(DYNAMAP) --input $(SLAM_BENCH_INPUT)
	@if ls $(BUILD_DIR)/python/dynamap/_core*.so >/dev/null 2>&1; then \
	  PYTHONPATH=$(BUILD_DIR)/python $(PYTHON) bench/bench_batch.py --source-dir . \
	    --count $(BENCH_BATCH_LOGS) --workers 2 --out out/bench-batch; \
	else echo "dynamap: the Python module is not built (pybind11-dev), fleet batch not timed"; fi

# The people detector's leg classifier (config/legs.yml.gz, built into dynamap as the same
# trees laid out flat, config/legs.forest.gz): grown on
# leg_tracker's real training bags, four marked-leg bags and two of the three lasers of the
# empty-room bag, and scored on the other two marked-leg bags and the third laser
# (docs/objects-and-people.md). The same bags give the same file.
LEG_DATA ?= $(DATASETS)/people/leg_training
legs: build
	$(DYNAMAP) train-legs \
	  $(foreach n,1 2 3 4,--positive $(LEG_DATA)/positive_$(n)_extracted.bag) \
	  --negative $(LEG_DATA)/negative_2.bag:/left_scan --negative $(LEG_DATA)/negative_2.bag:/right_scan \
	  $(foreach n,6 7,--validate-positive $(LEG_DATA)/positive_$(n)_extracted.bag) \
	  --validate-negative $(LEG_DATA)/negative_2.bag:/rear_scan --out config/legs.yml.gz \
	  --flat config/legs.forest.gz

# CLEAR MOT on the real people bags (leg_tracker's annotated person-following bag, unzipped
# into $(DATASETS)/people/) and the object table of a standing robot with people walking past.
PEOPLE_BAG ?= $(DATASETS)/people/person_following_outdoor_1.bag
eval-people: build
	@mkdir -p out/real
	@[ -f "$(PEOPLE_BAG)" ] || { echo "dynamap: $(PEOPLE_BAG) not found (unzip person_following_outdoor_1.bag.zip there)"; exit 1; }
	$(DYNAMAP) map --input $(PEOPLE_BAG) --scan-topic /scan_base2 --poses fixed --out out/real/person_following
	$(DYNAMAP) eval --people-bag $(PEOPLE_BAG) --scan-topic /scan_base2 --result out/real/person_following
	$(DYNAMAP) map --input $(DATASETS)/people/demo_stationary_simple_environment.bag --poses fixed \
	  --out out/real/demo_stationary
	@echo "demo_stationary: $$(($$(wc -l < out/real/demo_stationary/objects.csv) - 1)) object(s) in the table"

# Each config/scenarios/<name>.ini writes rawlogs/<name>/<name>.{rawlog,gt.txt,objects.csv,
# moves.csv,world.png}; the SimBundled tests fail when the committed files are stale.
SCENARIOS := arena corridors corridors_odom people tiny walkers storeroom
scenarios: build
	@for s in $(SCENARIOS); do \
	  $(DYNAMAP) simulate --scenario config/scenarios/$$s.ini --out rawlogs/$$s || exit 1; \
	done

# Each scenario is mapped with ground-truth poses into out/<name>/ and evaluated there
# (report.md, metrics.json); then one table of all of them beside the paper's. The scenarios of
# ODOMETRY_SCENARIOS are mapped from their odometry alone, with the pose graph (--poses slam,
# what auto chooses for such a log).
EVAL_SCENARIOS := arena corridors corridors_odom people walkers storeroom
ODOMETRY_SCENARIOS := corridors_odom
eval: build
	@for s in $(EVAL_SCENARIOS); do \
	  poses=ground_truth; \
	  case " $(ODOMETRY_SCENARIOS) " in *" $$s "*) poses=slam;; esac; \
	  $(DYNAMAP) map --config config/default.ini --poses $$poses \
	    --input rawlogs/$$s/$$s.rawlog --out out/$$s || exit 1; \
	  $(DYNAMAP) eval --scenario config/scenarios/$$s.ini --truth rawlogs/$$s/$$s \
	    --result out/$$s || exit 1; \
	  echo; \
	done
	@$(DYNAMAP) eval --summary $(addprefix out/,$(EVAL_SCENARIOS))

HELDOUT_SCENARIOS := $(basename $(notdir $(wildcard config/heldout/*.ini)))
eval-heldout: build
	@for s in $(HELDOUT_SCENARIOS); do \
	  $(DYNAMAP) simulate --scenario config/heldout/$$s.ini --out out/heldout/$$s/truth \
	    >/dev/null || exit 1; \
	  $(DYNAMAP) map --config config/default.ini --poses ground_truth \
	    --input out/heldout/$$s/truth/$$s.rawlog --out out/heldout/$$s || exit 1; \
	  $(DYNAMAP) eval --scenario config/heldout/$$s.ini --truth out/heldout/$$s/truth/$$s \
	    --result out/heldout/$$s || exit 1; \
	  echo; \
	done
	@$(DYNAMAP) eval --summary $(addprefix out/heldout/,$(HELDOUT_SCENARIOS))

# Table 3 on real scans: cylinders added to the Radish logs under $(DATASETS)/carmen/ (when
# present) by perturb --add-objects, each log mapped and scored into out/real/<log>-<seed>/.
REAL_LOGS := intel freiburg-079 freiburg-campus
REAL_SEEDS := 1 2 3
eval-real: build
	@dirs=""; for l in $(REAL_LOGS); do \
	  log=$(DATASETS)/carmen/$$l-corrected.log.gz; \
	  if [ ! -f $$log ]; then echo "dynamap: $$log not found, skipped"; continue; fi; \
	  for s in $(REAL_SEEDS); do o=out/real/$$l-$$s; \
	    $(DYNAMAP) perturb --input $$log --out $$o/truth --name $$l \
	      --add-objects objects=4,moves=10,seed=$$s >/dev/null || exit 1; \
	    $(DYNAMAP) map --config config/default.ini --input $$o/truth/$$l.rawlog --out $$o \
	      >/dev/null || exit 1; \
	    $(DYNAMAP) eval --truth $$o/truth/$$l --result $$o >/dev/null || exit 1; \
	    dirs="$$dirs $$o"; \
	  done; \
	done; [ -z "$$dirs" ] || $(DYNAMAP) eval --summary $$dirs

# The whole suite under ASan + UBSan. MRPT is not instrumented: .ci/lsan.supp is where leaks
# inside MRPT's own libraries would be suppressed (never ours).
ASAN_DIR ?= build-asan
SANITIZER_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/.ci/lsan.supp:print_suppressions=0 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
test-asan: deps
	cmake -S . -B $(ASAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDYNAMAP_SANITIZE=ON \
	  -DDYNAMAP_BUILD_BENCH=OFF
	cmake --build $(ASAN_DIR) -j $(JOBS)
	cd $(ASAN_DIR) && $(SANITIZER_ENV) ctest --output-on-failure --no-tests=error -j $(JOBS)

# libFuzzer targets (clang only; `make test` never needs clang). Each runs FUZZ_SECONDS from a
# corpus in build-fuzz/corpus/<target>/ seeded with fuzz/seeds/<target>/ and keeps growing it
# between runs (inputs up to 16 KB; 64 KB for bags, whose message definitions alone take 10 KB,
# and for ROS 2 bags, whose SQLite pages take 4 KB each).
# Run longer with FUZZ_SECONDS=3600 make fuzz, or one target directly:
#   build-fuzz/fuzz_rawlog -max_total_time=3600 build-fuzz/corpus/rawlog fuzz/seeds/rawlog
# A crash leaves its input in build-fuzz/crashes/; fix it, then keep the input in
# tests/fuzz_regressions/<target>/ (fuzz_regressions_test replays every file there).
FUZZ_DIR ?= build-fuzz
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := scenario carmen rawlog simplemap bag mcap db3 baseline config session
FUZZ_PACKAGES := clang libclang-rt-14-dev
fuzz-deps: deps
	@$(MAKE) --no-print-directory deps DEB_PACKAGES="$(FUZZ_PACKAGES)"

fuzz: fuzz-deps
	cmake -S . -B $(FUZZ_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DDYNAMAP_FUZZ=ON -DDYNAMAP_BUILD_TESTS=OFF -DDYNAMAP_BUILD_BENCH=OFF
	cmake --build $(FUZZ_DIR) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(FUZZ_DIR)/corpus/$$t $(FUZZ_DIR)/crashes/$$t; \
	  echo "dynamap: fuzzing $$t for $(FUZZ_SECONDS) s"; \
	  len=16384; case $$t in bag|mcap|db3) len=65536;; esac; \
	  $(SANITIZER_ENV) $(FUZZ_DIR)/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -max_len=$$len \
	    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
	    -artifact_prefix=$(FUZZ_DIR)/crashes/$$t/ $(FUZZ_DIR)/corpus/$$t fuzz/seeds/$$t \
	    2> $(FUZZ_DIR)/fuzz_$$t.log || { tail -40 $(FUZZ_DIR)/fuzz_$$t.log; exit 1; }; \
	  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" $(FUZZ_DIR)/fuzz_$$t.log; \
	done

# One run of 100,000+ simulated scans through the same Mapper as `dynamap map` (objects on),
# in a world and in one of four times its area; each in its own process, so each peak RSS is its
# own.
BENCH_LONG_SCANS ?= 100000
bench-long: build
	$(BUILD_DIR)/dynamap_bench_long --scans $(BENCH_LONG_SCANS) --scale 1
	$(BUILD_DIR)/dynamap_bench_long --scans $(BENCH_LONG_SCANS) --scale 2

# Odometry-only mapping of real logs: each corrected CARMEN log of $(DATASETS)/carmen/ made to
# drift by dynamap perturb (its default noise) with each seed of EVAL_SLAM_SEEDS, mapped with
# --poses slam $(EVAL_SLAM_ARGS) and scored against its known poses: raw odometry and slam
# aligned ATE, relative error over 1 m, consistency, loop closures, objects, CPU time. Seed 0 is
# the corrected poses as odometry, slam not allowed to keep them: how far slam's own matches
# pull the trajectory from the reference. The drifting logs are kept in EVAL_SLAM_OUT between
# runs. Nothing to do without the logs.
EVAL_SLAM_SEEDS ?= 0 1 2 3 4 5 6
EVAL_SLAM_OUT ?= out/eval-slam
EVAL_SESSIONS_OUT ?= out/eval-sessions
EVAL_SLAM_ARGS ?=
eval-slam: build
	@if ls $(DATASETS)/carmen/*-corrected.log.gz >/dev/null 2>&1; then \
	  bash bench/eval_slam.sh $(DYNAMAP) $(DATASETS) $(EVAL_SLAM_OUT) "$(EVAL_SLAM_SEEDS)" \
	    "$(EVAL_SLAM_ARGS)"; \
	else echo "dynamap: no $(DATASETS)/carmen/*-corrected.log.gz, nothing to evaluate"; fi

eval-sessions: build
	@bash bench/eval_sessions_sim.sh $(DYNAMAP) $(EVAL_SESSIONS_OUT)
	@if ls $(DATASETS)/carmen/*-corrected.log.gz >/dev/null 2>&1; then \
	  bash bench/eval_sessions.sh $(DYNAMAP) $(DATASETS) $(EVAL_SESSIONS_OUT); \
	else echo "dynamap: no $(DATASETS)/carmen/*-corrected.log.gz, nothing to evaluate"; fi

# Odometry-only mapping, side by side on corridors_odom: dynamap with ground-truth poses, with
# scan matching and with raw odometry, and MRPT's icp-slam (config/icp_slam.ini, adapted from
# MRPT's demo), each scored by `dynamap eval --trajectory` (absolute trajectory error). Then
# MRPT's odometry-only SENA log mapped with odometry and with scan matching. Installs mrpt-apps
# (icp-slam) when missing; `make test` does not need it.
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
	  $(DYNAMAP) eval --truth rawlogs/$$s --input $$log --trajectory $(COMPARE_OUT)/$$r || exit 1; \
	done; \
	for p in ground_truth scan_matching; do echo; \
	  $(DYNAMAP) eval --scenario config/scenarios/$$s.ini --truth rawlogs/$$s \
	    --result $(COMPARE_OUT)/$$s-$$p | head -8 || exit 1; \
	done
	@for p in odometry scan_matching slam; do \
	  $(DYNAMAP) map --config config/default.ini --poses $$p --input "$(SENA_LOG)" \
	    --out $(COMPARE_OUT)/sena-$$p || exit 1; \
	done; echo; for p in odometry scan_matching slam; do \
	  $(DYNAMAP) eval --input "$(SENA_LOG)" --trajectory $(COMPARE_OUT)/sena-$$p/poses.txt || exit 1; \
	done; echo "dynamap: SENA maps in $(COMPARE_OUT)/sena-odometry/, sena-scan_matching/ and sena-slam/"

format:
	clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	rm -rf $(BUILD_DIR) $(DEMO_DIR) $(ASAN_DIR) $(FUZZ_DIR) out
