"""The packaged FMU passes fmpy's validation and carries the committed model description."""

import zipfile

from conftest import ROOT, parameter_rows


def test_fmpy_validation_reports_no_problems(fmu_path):
    from fmpy.validation import validate_fmu

    assert validate_fmu(fmu_path) == []


def test_archive_layout_and_committed_model_description(fmu_path):
    with zipfile.ZipFile(fmu_path) as z:
        names = set(z.namelist())
        packed = z.read("modelDescription.xml").decode()
    assert {"modelDescription.xml", "binaries/linux64/WheelRailFriction.so", "documentation/index.html",
            "documentation/traction_creepage.png"} <= names
    assert any(n.startswith("resources/") for n in names)
    assert packed == (ROOT / "modelDescription" / "modelDescription.xml").read_text()


def test_model_description_declares_the_capabilities(fmu_path):
    from fmpy import read_model_description

    md = read_model_description(fmu_path)
    cs = md.coSimulation
    assert cs.modelIdentifier == "WheelRailFriction"
    assert cs.canHandleVariableCommunicationStepSize
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate and cs.providesDirectionalDerivative
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    assert inputs == {"creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force",
                      "rolling_speed", "wetness"} | GEOMETRY_INPUTS | {"semi_axis_a", "semi_axis_b"}
    for v in md.modelVariables:
        assert v.description, v.name
        if v.type == "Real":
            assert v.unit, v.name
    assert {c.name for c in md.logCategories} >= {"logEvents", "logStatusWarning", "logStatusError", "logAll"}


# parameters of the library (rows of kind "parameter") that the FMU takes as inputs of every step: the contact
# geometry
GEOMETRY_INPUTS = {"curvature_longitudinal", "curvature_lateral"}


def test_model_description_carries_the_parameter_specification(fmu_path):
    from fmpy import read_model_description

    variables = {v.name: v for v in read_model_description(fmu_path).modelVariables}
    rows = [r for r in parameter_rows() if r["fmu"]]
    assert {r["kind"] for r in rows} == {"input", "parameter"}
    for r in rows:
        v = variables[r["fmu"]]
        assert v.valueReference == r["value_reference"], r["fmu"]
        assert v.causality == ("input" if r["fmu"] in GEOMETRY_INPUTS else r["kind"]), r["fmu"]
        assert v.unit == r["unit"], r["fmu"]
        assert float(v.start) == r["default"], r["fmu"]
        if r["kind"] == "parameter":
            assert v.description == r["description"], r["fmu"]
            for bound in ("min", "max"):
                declared = getattr(v, bound)
                expected = r[bound] if r[bound + "_inclusive"] else None
                assert (None if declared is None else float(declared)) == expected, (r["fmu"], bound)
