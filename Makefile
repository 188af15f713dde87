# wheelrail — build, test, demo. `make test` runs every test (Rust and Python); `make demo` builds the FMU
# and runs it in a short fmpy co-simulation. The Python venv is created inside the repo (.venv, git-ignored)
# from the pinned requirements.txt.

CARGO ?= cargo
PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
FMU := target/fmu/WheelRailFriction.fmu
FMU3 := target/fmu/WheelRailFriction-fmi3.fmu

.PHONY: all build test test-rust test-python test-win64 examples lint demo clean venv fmu fmu-linux fmu-lib fmu-win64-lib model-description parameter-docs bench table slurm-test fuzz

all: build

build:
	$(CARGO) build --release --workspace

lint:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

# the FMU's shared library, which tests/fmu.rs loads, and its packager
fmu-lib:
	$(CARGO) build --release -p wheelrail-fmu
	$(CARGO) build --release -p wheelrail-cli --bin package-fmu

test-rust: fmu-lib
	$(CARGO) test --release --workspace

# the library's examples (examples/*.rs), each checking the physics it shows
examples:
	$(CARGO) run --release -p wheelrail --example point
	$(CARGO) run --release -p wheelrail --example sweep
	$(CARGO) run --release -p wheelrail --example table_lookup

# regenerate modelDescription/modelDescription.xml and modelDescription-fmi3.xml (FMI 3.0) from the variable
# table (tests check they are current)
model-description:
	$(CARGO) run --release -p wheelrail-cli --bin package-fmu -- --model-description modelDescription/modelDescription.xml
	$(CARGO) run --release -p wheelrail-cli --bin package-fmu -- --fmi3 --model-description modelDescription/modelDescription-fmi3.xml

# regenerate docs/parameters.md from the parameter specification src/params/spec.rs (a test checks it is current)
parameter-docs:
	$(CARGO) run --release -p wheelrail-cli --bin wheelrail -- parameters --markdown > docs/parameters.md

# the FMU's Windows DLL, cross-built with Debian's Rust and MinGW-w64 (tools/win64-build.sh: installs the
# toolchain when missing, as root; target x86_64-win7-windows-gnu, own target directory target/win64)
WIN64_DLL := target/win64/WheelRailFriction.dll
fmu-win64-lib:
	tools/win64-build.sh

# target/fmu/WheelRailFriction.fmu (FMI 2.0) and WheelRailFriction-fmi3.fmu (FMI 3.0) with both binaries,
# linux64 and win64 (the same library serves both versions)
fmu: fmu-lib fmu-win64-lib
	./target/release/package-fmu --library linux64=target/release/libWheelRailFriction.so \
		--library win64=$(WIN64_DLL) --out $(FMU)
	./target/release/package-fmu --fmi3 --library linux64=target/release/libWheelRailFriction.so \
		--library win64=$(WIN64_DLL) --out $(FMU3)

# the same FMUs with the linux64 binary only (no cross build: for development on Linux)
fmu-linux: fmu-lib
	./target/release/package-fmu --library target/release/libWheelRailFriction.so --out $(FMU)
	./target/release/package-fmu --fmi3 --library target/release/libWheelRailFriction.so --out $(FMU3)

$(VENV)/.installed: requirements.txt
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install --quiet --disable-pip-version-check -r requirements.txt
	touch $@

venv: $(VENV)/.installed

test-python: build fmu venv
	$(VPY) -m pytest -q tests/fmpy

# on Windows, under Wine: the library's unit tests (the table kernels' dispatch, the physics), then the win64
# binary against the linux64 binary: the same calls, statuses, logs and values, of FMI 2.0
# (tests/win64/test_win64.py) and FMI 3.0 (tests/win64/test_win64_fmi3.py); the comparison's figures in
# target/win64/comparison.json
test-win64: fmu venv
	tools/win64-build.sh --test-library
	$(VPY) -m pytest -q -s tests/win64

demo: fmu venv
	$(VPY) tools/demo.py --fmu $(FMU) --out target/demo

# a sharded table build as a Slurm array job on a temporary one-node cluster of this machine (installs Slurm
# and munge from Debian's packages when missing: needs root; WHEELRAIL_SKIP_SLURM=1 skips it), compared
# byte for byte with the same table built in one process
slurm-test:
	$(CARGO) build --release -p wheelrail-cli --bin wheelrail
	tools/slurm-test.sh

test: lint test-rust examples test-python test-win64 slurm-test

# the fuzzer of FMI call sequences (tests/fmu/fuzz.rs) at its full budget against the FMU's shared library:
# crashes, hangs and broken invariants fail, with the seed and a shrunk call log (`make test` runs 10 000;
# about 30 s of fuzzing on 2 cores, measured 100 000 sequences: 0 failures, crashes or hangs)
FUZZ_SEQUENCES ?= 100000
FUZZ_SEED ?= 16
fuzz: fmu-lib
	WHEELRAIL_FUZZ_SEQUENCES=$(FUZZ_SEQUENCES) WHEELRAIL_FUZZ_SEED=$(FUZZ_SEED) \
		$(CARGO) test --release -p wheelrail --test integration fmu::fuzz::sequences -- --exact --nocapture

# the MBS input trace of the trace benchmark and the demo (standard-library Python, deterministic)
TRACE := target/mbs_trace.csv
$(TRACE): tools/mbs_trace.py
	$(PYTHON) tools/mbs_trace.py --out $@

# criterion benchmarks in one run: Polach, constant-mu FASTSIM, exact dry and wet, 50-point sweeps, grid
# scaling, one exact MBS step per grid (7, 9, 15, 20, 30 cells per axis; dry and wet; cold, warm, warm with
# the set-up reused), table lookup, FMU fmi2DoStep (exact warm/cold, table), memory per FMU instance and the
# MBS trace through the FMU in modes table only, auto and exact, and exact on 7 x 7, 9 x 9, 15 x 15 and
# 20 x 20 grids (time per step, dry and wet, mean and p99, beside Polach's on the same trace; force errors;
# a few minutes); then
# the report with every time's ratio to Polach (target/bench/report.md)
bench: $(TRACE)
	$(CARGO) bench --workspace
	python3 tools/bench_report.py

clean:
	$(CARGO) clean
	rm -rf $(VENV)

# The committed lookup table (default parameters; the default running-surface contact, one geometry, on the
# axes of tools/default-contact-axes.toml: 693 000 points, 2158 s on 2 cores), then its verification against
# the exact solver (2000 random points). Tables over the contact geometry (tools/whole-range-axes.toml) are
# beyond one machine: on a Slurm cluster, `wheelrail table slurm --shards N --out DIR [--axes FILE]` writes
# the array job, the merge-and-verify job and DIR/submit.sh (docs/tables.md).
TABLE_DIR := fmu/resources/table
table:
	$(CARGO) run --release -p wheelrail-cli --bin wheelrail -- table build --axes tools/default-contact-axes.toml --out $(TABLE_DIR)
	$(CARGO) run --release -p wheelrail-cli --bin wheelrail -- table verify $(TABLE_DIR)
