"""Shared fixtures of the fmpy tests of WheelRailFriction.fmu.

The FMU is target/fmu/WheelRailFriction.fmu (override: WHEELRAIL_FMU) and the reference CLI is
target/release/wheelrail (override: WHEELRAIL_CLI); `make test-python` builds both first.
"""

import functools
import json
import os
import pathlib
import subprocess

import pytest
from fmpy import extract

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = pathlib.Path(os.environ.get("WHEELRAIL_FMU", ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
CLI = pathlib.Path(os.environ.get("WHEELRAIL_CLI", ROOT / "target" / "release" / "wheelrail"))
GRID = 12

# FMU outputs -> keys of `wheelrail point --json`
CLI_OUTPUTS = {
    "force_longitudinal": "force_x",
    "force_lateral": "force_y",
    "spin_moment": "spin_moment",
    "traction_coefficient": "traction_coefficient",
    "max_temperature": "max_temperature",
    "fluid_load_fraction": "fluid_load_fraction",
}


@pytest.fixture(scope="session")
def fmu_path():
    if not FMU.exists():
        pytest.fail(f"{FMU} is missing: build it with `make fmu`")
    return str(FMU)


@pytest.fixture(scope="session")
def unzipped_fmu(fmu_path, tmp_path_factory):
    """The FMU extracted once per session into pytest's temporary directory (removed with its old runs)."""
    return extract(fmu_path, unzipdir=str(tmp_path_factory.mktemp("fmu")))


TABLE = ROOT / "fmu" / "resources" / "table"


def cli():
    if not CLI.exists():
        pytest.fail(f"{CLI} is missing: build it with `make build`")
    return str(CLI)


@functools.lru_cache(maxsize=None)
def parameter_rows():
    """The rows of the parameter specification (`wheelrail parameters --json`, read once per session)."""
    out = subprocess.run([cli(), "parameters", "--json"], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def cli_flags():
    """FMU input and parameter names -> `wheelrail point` flags, from the parameter specification."""
    return {row["fmu"]: row["cli"] for row in parameter_rows() if row["fmu"] and row["cli"]}


def cli_point(table=False, **values):
    """`wheelrail point --json` for FMU-named inputs and parameters: on the test grid, or (table=True) by
    the default lookup table that the FMU bundles."""
    args = [cli(), "point", "--json"]
    args += ["--table", str(TABLE)] if table else ["--grid", f"{GRID},{GRID}"]
    flags = cli_flags()
    for name, value in values.items():
        args += [flags[name], repr(float(value))]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return json.loads(out)
