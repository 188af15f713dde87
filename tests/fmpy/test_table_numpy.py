"""The table files as NumPy reads them (docs/model.md §12.3, Storage): u16 codes are offset + step·code;
u16z/u16x streams decompress to the low and the high byte planes of the codes' differences along V and φ̂,
undone by `np.cumsum(…, axis=4)` then `axis=2` in uint16. With `--resolution F,T` the same recipe reads the
coarser codes: every value within half a step of the f32 build's, exact zeros kept, the step max(range/65 535,
F) (T for T_max)."""

import json
import lzma
import subprocess
import zlib

import numpy as np

from conftest import ROOT, cli

# the small fixture table's axes with three speed nodes (the V differences undone across more than one step)
AXES = (ROOT / "tests" / "fixtures" / "small-axes.toml").read_text().replace(
    "[speed]\npoints = [20.0, 40.0]", "[speed]\npoints = [10.0, 20.0, 40.0]")
assert "[10.0, 20.0, 40.0]" in AXES
PARAMS = "[grid]\nnx = 6\nny = 6\n"
CODECS = {"u16z": zlib.decompress, "u16x": lzma.decompress}


def build(tmp_path, name, *storage):
    (tmp_path / "axes.toml").write_text(AXES)
    (tmp_path / "params.toml").write_text(PARAMS)
    out = tmp_path / name
    subprocess.run([cli(), "table", "build", "--params", str(tmp_path / "params.toml"), "--axes",
                    str(tmp_path / "axes.toml"), "--out", str(out), *storage], check=True, capture_output=True)
    return out, json.loads((out / "table.json").read_text())


def shape(side):
    return tuple(len(a["points"]) for a in side["axes"])


def read(out, side):
    """Each output array as NumPy reads it, by the documented recipe of the table's storage."""
    storage = side.get("storage", "f32")
    arrays = {}
    for rec in side["outputs"]:
        if storage == "f32":
            arrays[rec["name"]] = np.load(out / rec["file"]).astype(np.float64)
            continue
        if storage == "u16":
            codes = np.load(out / rec["file"])
        else:
            raw = CODECS[storage]((out / rec["file"]).read_bytes())
            n = int(np.prod(shape(side)))
            planes = np.frombuffer(raw, dtype=np.uint8)
            assert planes.size == 2 * n
            diff = (planes[:n].astype(np.uint16) | (planes[n:].astype(np.uint16) << 8)).reshape(shape(side))
            codes = np.cumsum(np.cumsum(diff, axis=4, dtype=np.uint16), axis=2, dtype=np.uint16)
        q = rec["quantization"]
        arrays[rec["name"]] = q["offset"] + q["step"] * codes.astype(np.float64)
    return arrays


def test_numpy_reads_every_storage_and_the_coarser_codes_of_a_resolution(tmp_path):
    f32_dir, f32_side = build(tmp_path, "f32")
    exact = read(f32_dir, f32_side)
    u16 = read(*build(tmp_path, "u16", "--storage", "u16"))
    for storage in CODECS:
        got = read(*build(tmp_path, storage, "--storage", storage))
        for name, values in u16.items():
            assert np.array_equal(got[name], values), (storage, name)
    coarse_dir, coarse_side = build(tmp_path, "coarse", "--storage", "u16x", "--resolution", "1e-3,0.5")
    assert coarse_side["resolution"] == {"per_normal_force": 1e-3, "temperature": 0.5}
    coarse = read(coarse_dir, coarse_side)
    zeros = 0
    for rec in coarse_side["outputs"]:
        name, step = rec["name"], rec["quantization"]["step"]
        x = exact[name]
        floor = 0.5 if name == "max_temperature" else 1e-3
        assert step == max((x.max() - x.min()) / 65535, floor), name
        # half a step, plus the f32 rounding of the value the table keeps in memory
        assert np.all(np.abs(coarse[name] - x) <= 0.5 * step + 1e-7 * np.abs(x)), name
        assert np.all(coarse[name][x == 0.0] == 0.0), name
        zeros += int(np.count_nonzero(x == 0.0))
    assert zeros > 10
