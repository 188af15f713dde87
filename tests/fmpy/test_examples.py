"""The fmpy examples in examples/fmpy run against the built FMU and pass their own physical checks (those whose
name ends in `_fmi3` against the FMI 3.0 FMU)."""

import subprocess
import sys

import pytest

from conftest import ROOT
from test_fmi3 import FMU3

EXAMPLES = sorted((ROOT / "examples" / "fmpy").glob("*.py"))


def test_there_are_the_four_examples():
    assert {p.stem for p in EXAMPLES} >= {"traction_curve", "mbs_trace", "model_exchange", "vehicle_fmi3"}


@pytest.mark.parametrize("example", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs_and_its_checks_pass(example, fmu_path, tmp_path):
    fmu = FMU3 if example.stem.endswith("_fmi3") else fmu_path
    args = [sys.executable, str(example), "--fmu", str(fmu)]
    if "--out" in example.read_text():
        args += ["--out", str(tmp_path)]
    run = subprocess.run(args, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"{example.name} failed:\n{run.stdout}\n{run.stderr}"
    # every input has a signal or a value: fmpy does not warn of missing inputs
    assert "missing input" not in (run.stdout + run.stderr).lower(), run.stdout + run.stderr
    assert run.stdout.strip(), "the example printed nothing"
