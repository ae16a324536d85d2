# ORB accelerator: every target sets itself up; `make test` alone works on a fresh machine.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# ROS 2 from PyPI (rclpy, Kilted) has wheels for CPython 3.11 on x86_64 only, and its bootstrapper
# re-executes every Python start in its venv: a venv of its own (docs/ros2.md)
VENV_ROS2 := .venv-ros2
ROS2_STAMP := $(VENV_ROS2)/.installed
ROS2_PYTHON ?= $(shell command -v python3.11 2>/dev/null || echo $(PYTHON))
IMAGE  ?=
# CONFIG: for make sim and make ros-sim a named configuration (docs/configurations.md; empty: recommended-vga,
# sim-qvga); for make bitstream and make board-dryrun a board configuration of vivado/board.json (640x480,
# 1280x720, 1920x1080; empty: 1280x720 for make bitstream, all three for make board-dryrun). SCALES, PYRAMID,
# SECTORS, THRESHOLD, SIZE replace single values.
CONFIG ?=
SCALES ?=
PYRAMID ?=
SECTORS ?=
THRESHOLD ?=
JOBS   ?= 2

.PHONY: setup test test-tools test-all sim bench bench-sim bench-driver bench-stream bench-ros2 ros2-sim eval figures lint synth formal netlist-sim tools pattern docs views clean \
	help bitstream board-estimate board-dryrun ros-sim

help:
	@echo "make setup   create .venv (the project with test extras), .venv-ros2 (ROS 2 from PyPI) and .venv-pynq (tb/pynq) (idempotent)"
	@echo "make test    run the test suite (pytest -n $(JOBS), slow tests excluded)"
	@echo "make test-all  run every test, slow full-frame ones included"
	@echo "make sim     the complete accelerator in GHDL on the bundled image, the named configuration CONFIG="
	@echo "             (default recommended-vga; docs/configurations.md; IMAGE=, SIZE=WxH|native, SCALES=, PYRAMID=NUM:DEN,"
	@echo "             SECTORS=, THRESHOLD=, SELECTION=grid|all, BUDGET=;"
	@echo "             FAST=1: its synthesised netlist in Verilator; VIDEO=file: every frame of a video, fast; docs/fast-sim.md)"
	@echo "make bench   model speed benchmark (scripts/bench/bench_model.py)"
	@echo "make bench-sim  RTL simulation speed, one 640x480 frame (scripts/bench/bench_sim.py)"
	@echo "make bench-driver  per-frame CPU cost of the driver (banks and DDR ring) and the ROS message, 1,000, 2,000 and 5,000 features (docs/ros.md)"
	@echo "make bench-stream  per-frame cost of the feature stream (orb-accel serve): bytes, encode, decode, loopback (docs/stream.md)"
	@echo "make bench-ros2  per-frame CPU cost of the ROS 2 message, 1,000 features and a bank's capacity (docs/ros2.md)"
	@echo "make ros2-sim  the ROS 2 node on the simulated accelerator, publishing /orb_accel/features (IMAGE=; docs/ros2.md)"
	@echo "make ros-sim the ROS 1 node on the simulated accelerator, publishing /orb_accel/features (IMAGE=; docs/ros.md)"
	@echo "make eval    compare-fast, rotation-bench and scale-bench against OpenCV on the evaluation photos (STEP=1: ~7 min);"
	@echo "             then the held-out photographs (apt-get download, no root): scale-, track- and density-bench"
	@echo "make figures make eval, then copy its figures into docs/img (docs/img/README.md)"
	@echo "make lint    ruff, the import-layer contracts (lint-imports); GHDL synth check and vsg style of hdl/; tclint and the board dry run"
	@echo "make synth   LUT/FF/BRAM/DSP estimate of orb_core 640x480x1 + 1920x1080x2, checked (GHDL + yosys; about 10 min, cached;"
	@echo "             SIZE=1920x1080x2 or CONFIG=board-720p, TOP=orb_accel_top|orb_accel_zynq: also the logic-delay pass + worst paths (STA=0: not);"
	@echo "             GENERICS=\"STEP_NUM_g=5 STEP_DEN_g=4 SECTORS_g=64\": more generics of the top)"
	@echo "make formal  formal property checks of the interfaces (SymbiYosys on GHDL's Verilog; K=entity ...,"
	@echo "             MUTATIONS=0: without the planted bugs; docs/formal.md)"
	@echo "make netlist-sim  unit tests on GHDL's synthesised netlists (~15 min; K=entity, QUICK=1; docs/netlist-sim.md)"
	@echo "make views   regenerate every generated view from its data (orb_flow.gen.views; docs/conventions.md)"
	@echo "make tools   which of ghdl, yosys, python3 are installed, and how to install the rest"
	@echo "make docs    regenerate docs/entities/, docs/img/architecture.svg and docs/tools.md (orb_flow.gen)"
	@echo "make bitstream  the Zybo Z7-20 design in Vivado (CONFIG=board-vga|board-720p|board-1080p, VIVADO_LIBRARY=DIR,"
	@echo "             BOARD_REPO=DIR, VIVADO=; outputs in build/vivado/<config>; docs/board.md)"
	@echo "make board-dryrun  the Vivado build's TCL in tclsh against recording stubs, checked, with its table"
	@echo "make board-estimate  yosys estimate of orb_accel_zynq for each board configuration (slow, cached)"
	@echo "make power   power and energy a frame of each board configuration and the thesis's device, from yosys's"
	@echo "             resources and the netlist's activity in Verilator (CONFIG=board-vga ...; slow, cached; docs/power.md)"

$(STAMP): pyproject.toml
	@echo "make: setting up $(VENV) (the project and its test tools from PyPI: a few minutes the first time)"
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
		{ echo "error: Python 3.11 or newer is needed for make's venv (the tools read TOML with tomllib; found $$($(PYTHON) --version)); PYTHON=python3.11"; exit 1; }
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV) || \
		{ echo "error: '$(PYTHON) -m venv' failed; on Debian: apt-get install python3-venv"; exit 1; }
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	@touch $(STAMP)

$(ROS2_STAMP): sw/orb_ros2/requirements.txt
	@echo "make: setting up $(VENV_ROS2) (ROS 2 from PyPI and its messages: about a minute the first time)"
	@$(ROS2_PYTHON) -c 'import sys, platform; sys.exit(sys.version_info[:2] != (3, 11) or platform.machine() != "x86_64")' || \
		{ echo "error: the ROS 2 venv needs CPython 3.11 on x86_64 (PyPI's ROS 2 wheels; found $$($(ROS2_PYTHON) --version) on $$(uname -m)); ROS2_PYTHON=python3.11"; exit 1; }
	@test -x $(VENV_ROS2)/bin/python || $(ROS2_PYTHON) -m venv $(VENV_ROS2)
	$(VENV_ROS2)/bin/python -m pip install --quiet --upgrade pip
	$(VENV_ROS2)/bin/python -m pip install --quiet -r sw/orb_ros2/requirements.txt
	PYTHONPATH=.:sw $(VENV_ROS2)/bin/python -m orb_ros2.interfaces
	@touch $(ROS2_STAMP)

# The PYNQ checks' venv (tb/pynq, docs/pynq.md): PyPI's pynq pins numpy below 2, so it has a venv of its
# own, from tb/pynq/requirements.txt (about a minute and 240 MB the first time)
PYNQ_VENV  := .venv-pynq
PYNQ_STAMP := $(PYNQ_VENV)/.installed
$(PYNQ_STAMP): tb/pynq/requirements.txt
	@echo "make: setting up $(PYNQ_VENV) (PyPI's pynq for the PYNQ checks: about a minute the first time)"
	@test -x $(PYNQ_VENV)/bin/python || $(PYTHON) -m venv $(PYNQ_VENV) || \
		{ echo "error: '$(PYTHON) -m venv' failed; on Debian: apt-get install python3-venv"; exit 1; }
	$(PYNQ_VENV)/bin/python -m pip install --quiet --upgrade pip
	$(PYNQ_VENV)/bin/python -m pip install --quiet -r tb/pynq/requirements.txt
	@touch $(PYNQ_STAMP)

setup: $(STAMP) $(ROS2_STAMP) $(PYNQ_STAMP)

# the Debian tools the tests use (scripts/flow/check_tools.sh prints the apt-get line for a missing one)
TEST_TOOLS := ghdl yosys tclsh dtc cxx ros
# the tools first (a missing Debian package stops make test before the venvs' minutes, not after)
test-tools:
	@sh scripts/flow/check_tools.sh $(TEST_TOOLS)

test: test-tools $(STAMP) $(ROS2_STAMP) $(PYNQ_STAMP)
	@echo "make test: the venvs are ready and the Debian tools found; now the tests (pytest, $(JOBS) workers, the long simulations first; docs/results/test.json has the last fresh-clone time)"
	$(BIN)/python -m pytest -n $(JOBS) --maxschedchunk 1 -m "not slow" tb

test-all: test-tools $(STAMP) $(ROS2_STAMP) $(PYNQ_STAMP)
	$(BIN)/python -m pytest -n $(JOBS) --maxschedchunk 1 tb

FAST ?=
VIDEO ?=
sim: $(STAMP)
	$(BIN)/orb-accel sim $(if $(IMAGE),--image $(IMAGE)) $(if $(VIDEO),--video $(VIDEO)) \
		$(if $(CONFIG),--config $(CONFIG)) $(if $(SIZE),--size $(SIZE)) \
		$(if $(SCALES),--scales $(SCALES)) $(if $(PYRAMID),--step $(PYRAMID)) $(if $(SECTORS),--sectors $(SECTORS)) \
		$(if $(SELECTION),--selection $(SELECTION)) $(if $(BUDGET),--budget $(BUDGET)) \
		$(if $(THRESHOLD),--threshold $(THRESHOLD)) --out-dir build/sim \
		$(if $(filter 1 yes true,$(FAST)),--fast)

bench: $(STAMP)
	$(BIN)/python scripts/bench/bench_model.py

bench-sim: $(STAMP)
	$(BIN)/python scripts/bench/bench_sim.py

bench-driver: $(STAMP)
	@sh scripts/flow/check_tools.sh ros
	$(BIN)/python scripts/bench/bench_driver.py

bench-stream: $(STAMP)
	$(BIN)/python scripts/bench/bench_stream.py

# The per-frame cost of the ROS 2 message (docs/ros2.md), in the ROS 2 venv
bench-ros2: $(STAMP) $(ROS2_STAMP)
	PYTHONPATH=.:sw $(VENV_ROS2)/bin/python scripts/bench/bench_ros2.py

# The ROS 2 node against the simulated accelerator (docs/ros2.md); `ros2_client.py listen` or any ROS 2
# subscriber of /orb_accel/features (ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE as usual)
ros2-sim: $(STAMP) $(ROS2_STAMP)
	@sh scripts/flow/check_tools.sh ghdl
	$(BIN)/orb-accel ros2 --sim $(ROS_IMAGES) $(if $(CONFIG),--sim-config $(CONFIG))

# The ROS node against the simulated accelerator (docs/ros.md), with a roscore of its own when none answers at
# ROS_MASTER_URI; `rostopic echo /orb_accel/features` in another shell (after `eval $$(.venv/bin/orb-accel ros-env)`).
ROS_IMAGES ?= $(if $(IMAGE),$(IMAGE),golden_model/data/default_640x480.png)
ros-sim: $(STAMP)
	@sh scripts/flow/check_tools.sh ghdl ros
	$(BIN)/orb-accel ros --roscore --sim $(ROS_IMAGES) $(if $(CONFIG),--sim-config $(CONFIG))

STEP ?= 1
EVAL_PHOTOS := build/eval/photos
# the held-out photographs (Debian's opencv-doc and mate-backgrounds, orb-accel eval-photos); the tracking clips
# are made from the 8 largest (most room for the camera's motion) and OpenCV's sample video vtest.avi
EVAL_HELD := build/eval/held
EVAL_DEBS := build/eval/debian-cache
TRACK_PHOTOS := Wood Aqua Garden LadyBird TwoWings YellowFlower Storm Blinds
eval: $(STAMP)
	$(BIN)/python scripts/gen/sample_photos.py $(EVAL_PHOTOS) > /dev/null
	$(BIN)/orb-accel compare-fast $(EVAL_PHOTOS)/*.png --threshold 15 20 25 30 35 40 --out-dir build/eval/compare-fast
	$(BIN)/orb-accel rotation-bench $(EVAL_PHOTOS)/*.png --sectors 16 32 64 --step $(STEP) --threshold 20 \
		--scales 1 --out-dir build/eval/rotation-bench
	$(BIN)/orb-accel rotation-bench $(EVAL_PHOTOS)/*.png --sectors 32 --step $(STEP) --threshold 20 \
		--scales 1 --budget 1000 --out-dir build/eval/rotation-bench-grid
	$(BIN)/orb-accel scale-bench $(EVAL_PHOTOS)/*.png --out-dir build/eval/scale-bench
	$(BIN)/orb-accel eval-photos $(EVAL_HELD) --cache $(EVAL_DEBS)
	$(BIN)/orb-accel scale-bench $(EVAL_HELD)/640x480/*.png --extractors 5:4x5s64/g1000 cv-default@5:4x5s64/g1000 \
		--out-dir build/eval/scale-bench-held
	$(BIN)/orb-accel viewpoint-bench $(EVAL_HELD)/640x480/*.png --out-dir build/eval/viewpoint-bench-held
	$(BIN)/orb-accel trajectory-bench $(EVAL_HELD)/native/*.png --out-dir build/eval/trajectory-bench
	$(BIN)/orb-accel track-bench $(foreach p,$(TRACK_PHOTOS),$(EVAL_HELD)/native/$(p).png) \
		$$(ls $(EVAL_DEBS)/opencv-doc/usr/share/doc/opencv-doc/examples/data/vtest.avi 2>/dev/null) \
		--out-dir build/eval/track-bench
	$(BIN)/orb-accel density-bench $(EVAL_HELD)/native/*.png --sizes 640x480 1280x720 1920x1080 \
		--out-dir build/eval/density-bench

# the figures of docs/img (docs/img/README.md): the evaluation, copied
figures: eval
	cp build/eval/compare-fast/compare_fast.png build/eval/rotation-bench/rotation_bench.png \
		build/eval/scale-bench/scale_bench.png docs/img/

lint: $(STAMP)
	$(BIN)/ruff check golden_model sw tb scripts
	$(BIN)/ruff format --check golden_model sw tb scripts
	PYTHONPATH=tb $(BIN)/lint-imports
	@sh scripts/flow/check_tools.sh ghdl
	$(BIN)/python -m orb_flow.lint_hdl
	$(BIN)/tclint vivado sw/orb_flow/board/vivado_stub.tcl
	@sh scripts/flow/check_tools.sh tclsh
	$(BIN)/python -m orb_flow.board.dryrun

# Resource estimate (GHDL + yosys, no Vivado; docs/synthesis.md), checked against sw/orb_flow/synth_expected.json.
# SIZE=1920x1080x2 (WxHxSCALES, or a list) runs those sizes, CONFIG=board-720p (or a list) named configurations
# (docs/configurations.md), TOP= another top; STA=1 adds the logic-delay pass and its worst-paths report
# (build/synth/<top>/<config>/timing.md), the default when SIZE or CONFIG is given (STA=0: not);
# GENERICS="STEP_NUM_g=5 STEP_DEN_g=4 SECTORS_g=64" sets more generics of the top (the recommended 1080p build);
# UPDATE=1 writes the run's figures into synth_expected.json (an intended change; hdl/ committed).
# Plain python3 (no `make setup` needed); records are cached under build/synth.
TOP ?=
GENERICS ?=
STA ?= $(if $(SIZE)$(CONFIG),1,)
# formal property checks (docs/formal.md): the yowasp tools come with the formal extra (make setup)
MUTATIONS ?= 1
formal: $(STAMP)
	@sh scripts/flow/check_tools.sh ghdl
	$(BIN)/python -m orb_flow.formal $(K) $(if $(filter 0 no false,$(MUTATIONS)),--no-mutations)

synth:
	@sh scripts/flow/check_tools.sh ghdl yosys python3
	PYTHONPATH=sw $(PYTHON) -m orb_flow.synth --jobs $(JOBS) $(if $(TOP),--top $(TOP)) $(foreach c,$(SIZE),--config $(c)) \
		$(foreach c,$(CONFIG),--named $(c)) \
		$(foreach g,$(GENERICS),--generic $(g)) \
		$(if $(filter 1 yes true,$(STA)),--sta) $(if $(filter 1 yes true,$(UPDATE)),--update-expected)

# The cocotb tests of docs/netlist-sim.md on `ghdl synth --out=vhdl` netlists (~15 min); K=orb_overlay runs one
# entity, QUICK=1 leaves out the cases marked slow (~3 min).
K ?=
netlist-sim: $(STAMP)
	@sh scripts/flow/check_tools.sh ghdl
	$(BIN)/python -m orb_flow.netlist_sim $(foreach k,$(K),-k $(k)) $(if $(QUICK),--quick)

tools:
	@sh scripts/flow/check_tools.sh

pattern: $(STAMP)
	$(BIN)/python -m orb_flow.gen.pattern
	$(BIN)/python -m orb_flow.gen.pattern_vhdl

# every generated view from its data (orb_flow.gen.views: the registry of the generators; docs/conventions.md)
views: $(STAMP)
	$(BIN)/python -m orb_flow.gen.views

docs: $(STAMP)
	$(BIN)/python -m orb_flow.gen.entities
	$(BIN)/python -m orb_flow.gen.architecture
	$(BIN)/python -m orb_flow.gen.tools

# The Zybo Z7-20 build (docs/board.md). CONFIG is a board build's named configuration (board-vga,
# board-720p, board-1080p; or its vivado/board.json key 640x480, ...), default board-720p; VIVADO_LIBRARY is a checkout of Digilent's vivado-library (the pinned commit is in board.json);
# BOARD_REPO optionally Digilent's vivado-boards board_files. Plain python3: stops at once, one line, when
# Vivado or the library is missing.
VIVADO_LIBRARY ?=
BOARD_REPO ?=
VIVADO ?= vivado
bitstream:
	@PYTHONPATH=sw $(PYTHON) -m orb_flow.board.bitstream $(if $(CONFIG),--config $(CONFIG)) --vivado $(VIVADO) \
		$(if $(VIVADO_LIBRARY),--vivado-library $(VIVADO_LIBRARY)) $(if $(BOARD_REPO),--board-repo $(BOARD_REPO)) \
		--jobs $(JOBS)

# Post-route timing without Vivado (docs/pnr.md): the board top orb_accel_zynq of a named configuration
# (CONFIG, default board-vga) through GHDL, yosys and nextpnr-xilinx (openXC7); PNR_TIMEOUT limits each
# tool run in seconds. Plain python3: stops at once, one line, exit 2, when nextpnr-xilinx or its chip
# database is missing.
PNR_TIMEOUT ?=
.PHONY: pnr
pnr:
	@PYTHONPATH=sw $(PYTHON) -m orb_flow.pnr --named $(or $(CONFIG),board-vga) \
		$(if $(PNR_TIMEOUT),--timeout $(PNR_TIMEOUT))

# Power and energy a frame without Vivado (docs/power.md): yosys's resources x the netlist's toggles in
# Verilator on photographs x coefficients from published Vivado reports; CONFIG= one or more of
# board-vga board-720p board-1080p thesis-vga (default all). Slow the first time: a synthesis per
# configuration (cached in build/synth) and an activity build (cached in build/fastsim).
.PHONY: power
power: $(STAMP)
	@sh scripts/flow/check_tools.sh ghdl yosys python3
	PYTHONPATH=sw $(BIN)/python -m orb_flow.power $(if $(CONFIG),--configs $(CONFIG))

board-dryrun:
	@sh scripts/flow/check_tools.sh tclsh
	PYTHONPATH=sw $(PYTHON) -m orb_flow.board.dryrun --table $(foreach c,$(CONFIG),--config $(c))

board-estimate:
	@sh scripts/flow/check_tools.sh ghdl yosys python3
	PYTHONPATH=sw $(PYTHON) -m orb_flow.board.estimate --jobs $(JOBS)

clean:
	rm -rf build .pytest_cache
