# Thin wrapper over CMake: the README, CI and the benchmarks use these targets.
# Every target installs missing Debian packages first (scripts/install-deps.sh):
# `make demo` the demo group only, every other target all of them.

BUILD_DIR   ?= build
CROSS_DIR   ?= build-cross
TEENSY_DIR  ?= build-teensy
M4_DIR      ?= build-m4
ASAN_DIR    ?= build-asan
TSAN_DIR    ?= build-tsan
FUZZ_DIR    ?= build-fuzz
JOBS        ?= $(shell nproc)
FUZZ_SECONDS ?= 60
TEENSY_TOOLCHAIN := cmake/toolchains/teensy32.cmake
# DEBUG_INFO: the debug-information option that replaces -g in the Debug and
# RelWithDebInfo builds (SYROF_DEBUG_INFO); empty keeps -g. CI sets -g1
# (line tables only): a fifth to a third less compile time on the heavy
# sources; GCC emits the same code at every -g level (docs/building.md, "CI").
DEBUG_INFO  ?=

CMAKE_CONFIGURE = cmake -G Ninja -Wno-dev $(if $(DEBUG_INFO),-DSYROF_DEBUG_INFO=$(DEBUG_INFO))

.PHONY: all deps deps-demo build demo test package bench bench-m4 cross firmware test-m4 test-firmware-swarm test-slurm gradescope-prefix test-gradescope asan tsan fuzz clean

all: build

deps:
	@bash scripts/install-deps.sh all

deps-demo:
	@bash scripts/install-deps.sh demo

# Configures $(BUILD_DIR) when it has no cache yet, and again when Debian
# packages were installed after its last configure (dpkg's status file is
# newer than build.ninja): `make demo` installs fewer packages than `make
# test`, and the tests' optional finds (Chromium and libpng for the viewer's
# browser tests, Fast DDS for the interop test) must see what `make test`
# installs after it. Nothing is rebuilt unless configure changes a command.
define configure-build
@if [ ! -f $(BUILD_DIR)/CMakeCache.txt ] || [ /var/lib/dpkg/status -nt $(BUILD_DIR)/build.ninja ]; then \
  echo "$(CMAKE_CONFIGURE) -S . -B $(BUILD_DIR)"; $(CMAKE_CONFIGURE) -S . -B $(BUILD_DIR); fi
endef

build: deps
	$(configure-build)
	cmake --build $(BUILD_DIR) -j $(JOBS)

## demo: the main job: ten robots form a circle in the simulated lab
## (lab/scenarios/demo_circle.yaml); outputs in out/demo_circle/, with
## replay.html, the run's page (docs/viewer.md). A newcomer's first command:
## it installs the demo's package group only and builds DEMO_TARGETS only
## (about a third of the tree: no tests, benchmarks or test libraries);
## `make test` adds the rest in the same build folder.
## DEMO_TARGETS: the syrof command (it links the lab, the DDS swarm and the
## grader, and brings syrof-robot, which `syrof swarm` starts), the app host
## and libsyrof_app, which run and link a student's app (`syrof new`).
DEMO_TARGETS = syrof syrof-app-host syrof_app_shared
demo: deps-demo
	$(configure-build)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target $(DEMO_TARGETS)
	./$(BUILD_DIR)/bin/syrof run lab/scenarios/demo_circle.yaml --html

## test: the whole host test suite through ctest.
test: build
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

## test-slurm: a class graded as a Slurm job array on this machine (as root):
## munge, slurmctld and slurmd from Debian's packages with a private
## configuration, the job script and submit commands of docs/grading.md
## ("Spreading a class over machines"), a shard cancelled and resubmitted,
## and the merged class.csv and summary.txt checked against one machine's
## bytes (scripts/test-slurm.sh).
test-slurm: deps
	@bash scripts/install-deps.sh slurm
	$(configure-build)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target syrof syrof-app-host syrof_app_shared
	bash scripts/test-slurm.sh $(BUILD_DIR)

## gradescope-prefix: SyROF as a self-contained folder for the Gradescope
## bundle, $(BUILD_DIR)/gradescope-prefix/ (scripts/gradescope-prefix.sh):
## the programs grading runs, libsyrof_app, the headers and CMake package,
## and every library they need but glibc's and the C++ runtime's, with
## $$ORIGIN run paths; it fails if any ELF file asks for more than Ubuntu
## 22.04 has (glibc 2.35). `syrof gradescope` takes it from there.
gradescope-prefix: build
	bash scripts/gradescope-prefix.sh $(BUILD_DIR)

## test-gradescope: every assignment's bundle graded under Gradescope's
## default limits (half a core, 768 MB: a control group; as root): its
## reference must get full marks within GRADESCOPE_BUDGET_S (half of
## Gradescope's 10 minutes) and without being killed for memory; prints
## the wall time and peak memory of each (scripts/gradescope-limits.sh).
GRADESCOPE_BUDGET_S ?= 300
test-gradescope: gradescope-prefix
	bash scripts/gradescope-limits.sh --budget $(GRADESCOPE_BUDGET_S) $(BUILD_DIR)

## package: the Debian package $(BUILD_DIR)/syrof_<version>_<arch>.deb (CPack):
## the syrof command, the app host, libsyrof_app, the app API's headers, the
## CMake package and syrof-app.pc; Depends worked out by dpkg-shlibdeps.
package: build
	cmake --build $(BUILD_DIR) --target package

## bench: every program in bench/, each printing its figures.
bench: build
	@set -e; for program in $(BUILD_DIR)/bin/bench_*; do \
	  echo "== $$program"; "$$program"; echo; \
	done

## cross: core/ for the Teensy 3.2, with a size table per library.
cross: deps
	$(CMAKE_CONFIGURE) -S . -B $(CROSS_DIR) -DCMAKE_TOOLCHAIN_FILE=$(TEENSY_TOOLCHAIN) -DCMAKE_BUILD_TYPE=MinSizeRel
	cmake --build $(CROSS_DIR) -j $(JOBS)
	@bash scripts/size-table.sh $(CROSS_DIR)/lib

## firmware: syrof-robot for the Teensy 3.2 in $(TEENSY_DIR)/bin: ELF, Intel
## HEX (teensy-loader-cli --mcu=TEENSY32 -w -v syrof-robot.hex), linker map,
## and the size table; the link fails past the budgets (flash 128 KB, RAM
## 48 KB) or the chip. APP=path/app.c compiles a student's C app in place of
## the built-in one (docs/firmware.md, "Teensy 3.2 board").
APP ?=
firmware: deps
	$(CMAKE_CONFIGURE) -S . -B $(TEENSY_DIR) -DCMAKE_TOOLCHAIN_FILE=$(TEENSY_TOOLCHAIN) -DCMAKE_BUILD_TYPE=MinSizeRel \
	  -DSYROF_TEENSY_IMAGE=ON -DSYROF_FIRMWARE_APP=$(if $(APP),$(abspath $(APP)))
	cmake --build $(TEENSY_DIR) -j $(JOBS) --target syrof-robot
	@bash scripts/firmware-size.sh $(TEENSY_DIR)/bin/syrof-robot.elf

## test-m4: core's unit tests and the firmware kernel's tests on an emulated Cortex-M4 (qemu mps2-an386),
## and the robot image under qemu (its configuration block written by the host build's syrof-firmware-config).
test-m4: deps
	$(configure-build)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target syrof-firmware-config
	$(CMAKE_CONFIGURE) -S . -B $(M4_DIR) -DCMAKE_TOOLCHAIN_FILE=$(TEENSY_TOOLCHAIN) -DSYROF_M4_TESTS=ON -DCMAKE_BUILD_TYPE=Release \
	  -DSYROF_HOST_TOOLS_DIR=$(abspath $(BUILD_DIR))/bin
	cmake --build $(M4_DIR) -j $(JOBS)
	ctest --test-dir $(M4_DIR) --output-on-failure -j $(JOBS)

## test-firmware-swarm: an emulated swarm of real firmware (docs/firmware.md,
## "The emulated swarm"): SWARM_ROBOTS qemu instances of syrof-robot-mps2
## (4 in CI and on machines with fewer than 4 cores, 8 otherwise: two
## instances a core, as CI runs them) joined through syrof-firmware-swarm, which plays the
## world of SWARM_SCENARIO, the robots' sensors and the lab's radio channel.
## Two runs: no loss (every robot must start one epoch COOPERATIVE) and
## SWARM_LOSS loss (P3 must stay 0); in both the largest estimation error
## must stay within SWARM_MAX_ESTIMATION_ERROR_M and the replay must read
## back; outputs (metrics.json, replay) in out/firmware-swarm/{no-loss,loss}/.
## A third, shorter run plays SWARM_FAULTS_SCENARIO's faults (4 robots: a late
## join, a pause, a partition, a crash; --expect-faults: the crashed robot is
## removed from the others' maps, the paused one comes back, the joiner
## becomes a member; P3 0) into out/firmware-swarm/faults/.
## The same faults run again with 10 % loss under seeded stress (--stress
## SWARM_STRESS_SEED: qemu and host stalls of 10-200 ms, late beacons;
## docs/firmware.md, "Stress"): P3 0, every line parsed, the replay whole;
## a failure prints the command that reruns it. Into out/firmware-swarm/stress/.
## The two runs take the guests' clocks from -icount shift=SWARM_ICOUNT (-1:
## the host's clock, syrof-firmware-swarm's default, which lines rounds up
## best when every instance has a core; four instances saturate 2 cores and
## their late timer interrupts then push estimation errors past 1 m); the
## faults run is on the host's clock. About 1.5 x SWARM_SECONDS each.
## Then the base station (docs/bridge.md): 4 robots for SWARM_BRIDGE_SECONDS with
## --base-station, syrof-bridge connected; its replay must hold every robot with
## its epochs advancing, COOPERATIVE epochs, each robot's epoch starts as the
## robot reported them, nothing rejected (scripts/bridge-hears-firmware-swarm.sh),
## into out/firmware-swarm/bridge/. Then the swarm's own live page
## (syrof-firmware-swarm --live; tests/firmware/swarm, ctest -R FirmwareSwarmLive):
## 4 robots for 4 s, the page's /events read whole (the header, the
## replay's rounds, every robot RUNNING, the end linking the replay) and the
## page opened in headless Chromium while 3 robots run for 10 s (every robot RUNNING),
## and lab/scenarios/gather.yaml on the starter image for 2 s (ctest -R
## FirmwareSwarmImageApp): one warning line that the image runs circle, and
## the replay's header and metrics.json naming circle.
## Last, the lab against the firmware: SWARM_COMPARE_SCENARIO in `syrof run`
## and on the emulated swarm (--realtime), which must start the same epochs
## in the same modes with the same members (scripts/firmware-agrees-with-lab.sh,
## up to five tries when they disagree), into out/firmware-swarm/compare/; then
## the same under each weaker activation model, SWARM_COMPARE_SSYNC_SCENARIO and
## SWARM_COMPARE_ASYNC_SCENARIO (the files the lab and DDS are compared on,
## docs/activation.md; each robot must also have looked exactly when its
## schedule says), into out/firmware-swarm/compare-ssync/ and compare-async/
## (about 25 s each when the first try agrees). Then a message assignment
## whose robots need their private inputs: SWARM_COMPARE_INPUTS_SCENARIO
## (assignments/strongest's scenario on 4 robots, each told its own charge on
## its boot line) with the strongest reference in the lab (--app, its
## library) and on the image built with it (syrof-robot-mps2-strongest), the
## robots' true positions compared too (within SWARM_COMPARE_POSE_TOLERANCE_M),
## and the apps' payloads in every map epoch by epoch (syrof compare --payloads:
## the charges the robots share), into out/firmware-swarm/compare-inputs/ (21 s
## here when the first try agrees).
## Then drones: SWARM_COMPARE_DRONES_SCENARIO (4 drones spread onto a circle
## on the default arena, each told its kind on its boot line: docs/firmware.md,
## "Robot kinds") in the lab and on the emulated swarm for
## SWARM_COMPARE_DRONES_SECONDS, the robots' true positions compared too,
## into out/firmware-swarm/compare-drones/, and the same with all three kinds,
## SWARM_COMPARE_KINDS_SCENARIO (two omni robots, a rover and a drone), into
## out/firmware-swarm/compare-kinds/ (about 11 s each when the first try agrees).
SWARM_ICOUNT  ?= 4
SWARM_ROBOTS  ?= $(if $(CI),4,$(shell [ $$(nproc) -ge 4 ] && echo 8 || echo 4))
SWARM_SECONDS ?= $(if $(CI),30,60)
SWARM_LOSS    ?= 0.3
SWARM_SCENARIO ?= lab/scenarios/firmware_swarm.yaml
SWARM_MAX_ESTIMATION_ERROR_M ?= 1.0
SWARM_FAULTS_SCENARIO ?= lab/scenarios/firmware_faults.yaml
SWARM_FAULTS_SECONDS ?= 14
SWARM_STRESS_SEED ?= 1
SWARM_COMPARE_SCENARIO ?= lab/scenarios/four_runtimes.yaml
SWARM_COMPARE_SSYNC_SCENARIO ?= tests/sim_dds/scenarios/ssync_runtimes.yaml
SWARM_COMPARE_ASYNC_SCENARIO ?= tests/sim_dds/scenarios/async_runtimes.yaml
SWARM_COMPARE_INPUTS_SCENARIO ?= tests/firmware/swarm/strongest_4.yaml
SWARM_COMPARE_INPUTS_APP ?= $(BUILD_DIR)/tests/grader/assignment/submissions/strongest/reference/libstrongest.so
SWARM_COMPARE_POSE_TOLERANCE_M ?= 0.25
SWARM_COMPARE_DRONES_SCENARIO ?= tests/firmware/swarm/drones_4.yaml
SWARM_COMPARE_DRONES_SECONDS ?= 10
SWARM_COMPARE_KINDS_SCENARIO ?= tests/firmware/swarm/three_kinds_4.yaml
SWARM_BRIDGE_SECONDS ?= 8
test-firmware-swarm: deps
	$(configure-build)
	$(CMAKE_CONFIGURE) -S . -B $(M4_DIR) -DCMAKE_TOOLCHAIN_FILE=$(TEENSY_TOOLCHAIN) -DSYROF_M4_TESTS=ON -DCMAKE_BUILD_TYPE=Release
	cmake --build $(M4_DIR) -j $(JOBS) --target syrof-robot-mps2 syrof-robot-mps2-strongest
	cmake --build $(BUILD_DIR) -j $(JOBS) --target syrof-firmware-swarm syrof syrof-bridge submission_strongest_reference \
	  test_firmware_swarm_live test_firmware_swarm_live_browser test_firmware_swarm_image_app
	./$(BUILD_DIR)/bin/syrof-firmware-swarm --image $(M4_DIR)/bin/syrof-robot-mps2.elf --scenario $(SWARM_SCENARIO) \
	  --robots $(SWARM_ROBOTS) --seconds $(SWARM_SECONDS) --loss 0 --seed 1 --icount $(SWARM_ICOUNT) \
	  --out out/firmware-swarm/no-loss --expect-cooperative --max-estimation-error $(SWARM_MAX_ESTIMATION_ERROR_M)
	./$(BUILD_DIR)/bin/syrof-firmware-swarm --image $(M4_DIR)/bin/syrof-robot-mps2.elf --scenario $(SWARM_SCENARIO) \
	  --robots $(SWARM_ROBOTS) --seconds $(SWARM_SECONDS) --loss $(SWARM_LOSS) --seed 2 --icount $(SWARM_ICOUNT) \
	  --out out/firmware-swarm/loss \
	  --max-estimation-error $(SWARM_MAX_ESTIMATION_ERROR_M)
	./$(BUILD_DIR)/bin/syrof-firmware-swarm --image $(M4_DIR)/bin/syrof-robot-mps2.elf --scenario $(SWARM_FAULTS_SCENARIO) \
	  --seconds $(SWARM_FAULTS_SECONDS) --icount -1 --out out/firmware-swarm/faults --expect-faults
	./$(BUILD_DIR)/bin/syrof-firmware-swarm --image $(M4_DIR)/bin/syrof-robot-mps2.elf --scenario $(SWARM_FAULTS_SCENARIO) \
	  --seconds $(SWARM_FAULTS_SECONDS) --icount -1 --loss 0.1 --out out/firmware-swarm/stress --stress $(SWARM_STRESS_SEED)
	bash scripts/bridge-hears-firmware-swarm.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2.elf \
	  out/firmware-swarm/bridge 4 $(SWARM_BRIDGE_SECONDS)
	SYROF_REQUIRE_MPS2_IMAGE=1 SYROF_MPS2_ROBOT_IMAGE=$(abspath $(M4_DIR))/bin/syrof-robot-mps2.elf \
	  ctest --test-dir $(BUILD_DIR) --output-on-failure --no-tests=error -R '^FirmwareSwarm(Live|ImageApp)'
	bash scripts/firmware-agrees-with-lab.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2.elf \
	  $(SWARM_COMPARE_SCENARIO) out/firmware-swarm/compare
	bash scripts/firmware-agrees-with-lab.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2.elf \
	  $(SWARM_COMPARE_SSYNC_SCENARIO) out/firmware-swarm/compare-ssync
	bash scripts/firmware-agrees-with-lab.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2.elf \
	  $(SWARM_COMPARE_ASYNC_SCENARIO) out/firmware-swarm/compare-async
	LAB_APP=$(SWARM_COMPARE_INPUTS_APP) POSE_TOLERANCE_M=$(SWARM_COMPARE_POSE_TOLERANCE_M) PAYLOADS=1 \
	  bash scripts/firmware-agrees-with-lab.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2-strongest.elf \
	  $(SWARM_COMPARE_INPUTS_SCENARIO) out/firmware-swarm/compare-inputs
	POSE_TOLERANCE_M=$(SWARM_COMPARE_POSE_TOLERANCE_M) FIRMWARE_SECONDS=$(SWARM_COMPARE_DRONES_SECONDS) \
	  bash scripts/firmware-agrees-with-lab.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2.elf \
	  $(SWARM_COMPARE_DRONES_SCENARIO) out/firmware-swarm/compare-drones
	POSE_TOLERANCE_M=$(SWARM_COMPARE_POSE_TOLERANCE_M) FIRMWARE_SECONDS=$(SWARM_COMPARE_DRONES_SECONDS) \
	  bash scripts/firmware-agrees-with-lab.sh $(BUILD_DIR) $(M4_DIR)/bin/syrof-robot-mps2.elf \
	  $(SWARM_COMPARE_KINDS_SCENARIO) out/firmware-swarm/compare-kinds

## bench-m4: instruction counts on the emulated Cortex-M4 (bench/m4), one image each.
QEMU_M4 = qemu-system-arm -M mps2-an386 -nographic -monitor none -serial null \
          -semihosting-config enable=on,target=native -icount shift=0
bench-m4: deps
	$(CMAKE_CONFIGURE) -S . -B $(M4_DIR) -DCMAKE_TOOLCHAIN_FILE=$(TEENSY_TOOLCHAIN) -DSYROF_M4_TESTS=ON -DCMAKE_BUILD_TYPE=Release
	cmake --build $(M4_DIR) -j $(JOBS)
	@set -e; for image in $(M4_DIR)/bin/bench_m4_*.elf; do \
	  [ -e "$$image" ] || continue; \
	  echo "== $$image"; $(QEMU_M4) -kernel "$$image"; echo; \
	done

## asan: core's, queries' and lab's tests once more under AddressSanitizer and UBSan.
## Only what those labels' tests need is built (the targets tests_<label>,
## cmake/SyrofHelpers.cmake): not the CLI (with the DDS swarm and the grader
## it links), the app host's, the grader's, the viewer's browser test or the
## exhaustive exploration. The parsers of untrusted input (scenarios, replays,
## assignments' scenario files, beacons) are lab's and core's, and run here;
## the CLI's own tests were a sixth of the CI run under ASan (docs/building.md).
ASAN_LABELS = core queries lab
# Left out under the sanitizers: the twenty-seed safety runs (100 runs;
# stage 1 runs them), the 200-robot adversarial crowd and its joiner case (177 s
# under ASan at -O0 against 12 s in stage 1, and last to finish); the same
# code runs under ASan in the smaller adversarial scenarios. The thread
# mode's byte-identity runs (SimulationThreadsTest, about 60 s under ASan;
# every one of them compares a run on 1, 2 and 3 threads) keep their short
# run here; `make tsan` runs it for data races and stage 1 runs them all.
# The search's pruning self-tests (SearchTest.EveryPruned*: every pruned
# pattern run twice more, 20 s in stage 1) run in stage 1 only; the
# search's other tests, pruning included, run here.
ASAN_EXCLUDE = crowdx200xshort|TwentySeeds|AJoinerWaitsForARobotThatCouldNotStop|SimulationThreadsTest\.(ACrowdOf200|AppFaults|Bursts|LossAndEvery|Clocks)|SearchTest\.EveryPruned
empty :=
space := $(empty) $(empty)
asan: deps
	$(CMAKE_CONFIGURE) -S . -B $(ASAN_DIR) -DSYROF_SANITIZE=ON -DSYROF_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=Debug
	cmake --build $(ASAN_DIR) -j $(JOBS) --target $(addprefix tests_,$(ASAN_LABELS))
	ctest --test-dir $(ASAN_DIR) --output-on-failure -j $(JOBS) -L '^($(subst $(space),|,$(ASAN_LABELS)))$$' -E '$(ASAN_EXCLUDE)'

## tsan: the tests where threads meet (the POSIX port, the broker across
## threads, the robot's receive edge, the lab's --threads) under ThreadSanitizer. Their suites:
## TSAN_SUITES; add a suite there when a test starts threads.
TSAN_TESTS = test_core_os_posix test_core_pubsub_threads test_core_runtime_threads test_lab_sim_threads
TSAN_SUITES = ^(PosixPortTest\.|BrokerThreadsTest\.|RobotThreadsTest\.|SimulationThreadsTest\.ShortRun)
tsan: deps
	$(CMAKE_CONFIGURE) -S . -B $(TSAN_DIR) -DSYROF_TSAN=ON -DSYROF_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=Debug
	cmake --build $(TSAN_DIR) -j $(JOBS) --target $(TSAN_TESTS)
	TSAN_OPTIONS=halt_on_error=1 ctest --test-dir $(TSAN_DIR) --output-on-failure --no-tests=error -j $(JOBS) -R '$(TSAN_SUITES)'

## fuzz: libFuzzer on the beacon decoder, the DDS sample checks, the
## radio link's frame decoder (docs/radio-link.md), the base station
## (docs/bridge.md) and the robot's configuration block (docs/firmware.md),
## FUZZ_SECONDS each.
fuzz: deps
	CC=clang CXX=clang++ $(CMAKE_CONFIGURE) -S . -B $(FUZZ_DIR) -DSYROF_FUZZ=ON -DSYROF_BUILD_TESTS=OFF -DSYROF_BUILD_BENCH=OFF
	cmake --build $(FUZZ_DIR) -j $(JOBS) --target fuzz_beacon_decode fuzz_beacon_sample fuzz_radio_link fuzz_bridge fuzz_config_block
	mkdir -p $(FUZZ_DIR)/corpus/beacon $(FUZZ_DIR)/corpus/beacon_sample $(FUZZ_DIR)/corpus/radio_link $(FUZZ_DIR)/corpus/bridge \
	  $(FUZZ_DIR)/corpus/config_block
	./$(FUZZ_DIR)/bin/fuzz_beacon_decode -max_total_time=$(FUZZ_SECONDS) -seed=1 $(FUZZ_DIR)/corpus/beacon
	./$(FUZZ_DIR)/bin/fuzz_beacon_sample -max_total_time=$(FUZZ_SECONDS) -seed=1 $(FUZZ_DIR)/corpus/beacon_sample
	./$(FUZZ_DIR)/bin/fuzz_radio_link -max_total_time=$(FUZZ_SECONDS) -seed=1 $(FUZZ_DIR)/corpus/radio_link
	./$(FUZZ_DIR)/bin/fuzz_bridge -max_total_time=$(FUZZ_SECONDS) -seed=1 $(FUZZ_DIR)/corpus/bridge
	./$(FUZZ_DIR)/bin/fuzz_config_block -max_total_time=$(FUZZ_SECONDS) -seed=1 $(FUZZ_DIR)/corpus/config_block

clean:
	rm -rf $(BUILD_DIR) $(CROSS_DIR) $(TEENSY_DIR) $(M4_DIR) $(ASAN_DIR) $(TSAN_DIR) $(FUZZ_DIR)
