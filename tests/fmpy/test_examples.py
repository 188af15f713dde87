"""The fmpy examples in examples/fmpy run against the built FMU and pass their own physical checks."""

import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = sorted((ROOT / "examples" / "fmpy").glob("*.py"))


def test_there_are_the_three_examples():
    assert {p.stem for p in EXAMPLES} >= {"traction_curve", "mbs_trace", "model_exchange"}


@pytest.mark.parametrize("example", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs_and_its_checks_pass(example, fmu_path, tmp_path):
    args = [sys.executable, str(example), "--fmu", fmu_path]
    if "--out" in example.read_text():
        args += ["--out", str(tmp_path)]
    run = subprocess.run(args, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"{example.name} failed:\n{run.stdout}\n{run.stderr}"
    # every input has a signal or a value: fmpy does not warn of missing inputs
    assert "missing input" not in (run.stdout + run.stderr).lower(), run.stdout + run.stderr
    assert run.stdout.strip(), "the example printed nothing"
