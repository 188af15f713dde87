"""The README's interface tables state the FMU's variables as its modelDescription.xml does: every input,
output and parameter under its own heading, with its value reference and unit."""

import re

from fmpy import read_model_description

from conftest import ROOT

HEADINGS = {"input": "**Inputs**", "output": "**Outputs:**", "parameter": "**Parameters**"}
# units as the README writes them
WRITTEN = {"N.m": "N·m", "Pa.s": "Pa·s", "1": "-"}


def table_after(text, heading):
    """The rows of the first Markdown table after `heading`."""
    rest = text[text.index(heading):]
    lines = rest.splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("|"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append(line)
    return rows


def test_readme_tables_list_every_variable_with_its_value_reference_and_unit(fmu_path):
    readme = (ROOT / "README.md").read_text()
    md = read_model_description(fmu_path)
    tables = {c: table_after(readme, h) for c, h in HEADINGS.items()}
    for v in md.modelVariables:
        rows = [r for r in tables[v.causality] if re.search(rf"`{v.name}` \({v.valueReference}\)", r)]
        others = [c for c, t in tables.items() if c != v.causality and any(f"`{v.name}` (" in r for r in t)]
        assert len(rows) == 1 and not others, f"{v.name} ({v.causality}): rows {rows}, also under {others}"
        if v.type == "Real":
            unit = WRITTEN.get(v.unit, v.unit)
            cells = [c.strip() for c in rows[0].split("|")]
            assert any(c == unit or f"[{unit}]" in c for c in cells), f"{v.name}: unit {unit} not in {rows[0]}"
