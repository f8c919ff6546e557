"""Sample-file readers and writers (metro.instruments.readers): round trips and bad input."""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from metro.core.base.errors import DataError, UnitError
from metro.instruments.readers import common as readers_common
from metro.instruments.readers import text as readers_text
from metro.instruments.readers import writing as readers_writing
from metro.instruments.readers import (SampleTable, parse_header_cell, read_samples,
                                       write_samples_csv, write_samples_npy)


def _bits(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def _series(n: int = 200, dt: float = 0.01, seed: int = 1) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    return {"time": np.arange(n) * dt, "output": rng.normal(0.0, 3.0, n)}


UNITS = {"time": "s", "output": "P"}


def _csv(tmp_path: Path, text: str, name: str = "seg.csv") -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8"))
    return path


def _rows(values, t0: int = 0) -> str:
    return "".join(f"{t0 + i},{v}\n" for i, v in enumerate(values))


GOOD_HEAD = "time [s],output [P]\n"


def _expect(path: Path, fragments=(), *, field: str | None = None, exc=DataError, **kw):
    """read_samples(path) must raise ``exc`` whose message names the file and fragments."""
    with pytest.raises(exc) as info:
        read_samples(path, **kw)
    err = info.value
    text = str(err)
    assert str(path) in text
    if field is not None:
        assert err.field == field, err.field
        assert f"field '{field}'" in text
    for fragment in fragments:
        assert fragment in text, (fragment, text)
    return err


# --------------------------------------------------------------------------- round trips


def test_csv_round_trip_is_exact(tmp_path):
    data = _series(500)
    data["count"] = np.arange(500, dtype=np.int64) * 7 - 1000
    path = write_samples_csv(tmp_path / "a.csv", data, {**UNITS, "count": "LSB"})
    table = read_samples(path, expected_interval_s=0.01, background_hash=False)
    assert isinstance(table, SampleTable)
    assert table.format == "csv" and table.n_rows == 500
    assert table.units == {"time": "s", "output": "P", "count": "LSB"}
    assert list(table.columns) == ["time", "output", "count"]
    for name, values in data.items():
        col = table.columns[name]
        assert col.dtype == np.float64 and col.ndim == 1
        assert not col.flags.writeable
        assert np.array_equal(_bits(col), _bits(values))
    assert table.sample_interval_s == pytest.approx(0.01, rel=1e-12)
    assert table.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    # integers are written as integers
    assert path.read_text().splitlines()[2].endswith(",-993")


def test_tsv_round_trip_and_units_with_symbols(tmp_path):
    data = {"time": np.arange(50) * 0.5, "rate": np.linspace(-3, 3, 50)}
    units = {"time": "s", "rate": "°/h"}
    for suffix in (".tsv", ".txt"):
        path = write_samples_csv(tmp_path / f"r{suffix}", data, units)
        assert "\t" in path.read_text(encoding="utf-8").splitlines()[0]
        table = read_samples(path)
        assert table.format == "tsv"
        assert table.units == units
        assert np.array_equal(table["rate"], data["rate"])


def test_large_offset_values_read_exactly(tmp_path):
    texts = ["10000000.1", "1000000000000.1", "999999999999.9", "1e12", "1234567.0000001",
             "0.1", "-2.5e-308", "4.9e-324", "1.7976931348623157e308", "9007199254740993"]
    path = _csv(tmp_path, "# exact parsing\nvalue [P]\n" + "\n".join(texts) + "\n")
    table = read_samples(path)
    assert np.array_equal(_bits(table["value"]), _bits(np.array([float(t) for t in texts])))
    assert table["value"][0] == 10000000.1


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=40))
def test_random_floats_round_trip_exactly(tmp_path, values):
    x = np.array(values, dtype=np.float64)
    path = write_samples_csv(tmp_path / "h.csv", {"x": x, "y": x[::-1].copy()},
                             {"x": "1", "y": "mV"})
    table = read_samples(path, time_column=None)
    assert np.array_equal(_bits(table["x"]), _bits(x))  # bit-exact, -0.0 included
    assert np.array_equal(_bits(table["y"]), _bits(x[::-1]))


def test_header_conventions(tmp_path):
    text = (
        "\ufeff# station: simulated\n# operator: \"A. N. Other\"\n\n"
        '"time [s]", "output [P]" ,ratio [1]\r\n'
        "0,1.5,1\r\n1, 2.5 ,\"2\"\r\n\r\n2,3.5,3\r\n"
    )
    table = read_samples(_csv(tmp_path, text))
    assert table.units == {"time": "s", "output": "P", "ratio": "1"}
    assert table["output"].tolist() == [1.5, 2.5, 3.5]
    assert table["ratio"].tolist() == [1.0, 2.0, 3.0]
    assert parse_header_cell("rate [°/h]") == ("rate", "°/h")
    assert parse_header_cell("rate") is None


def test_delimiter_is_sniffed_from_the_header(tmp_path):
    path = _csv(tmp_path, "time [s]\toutput [P]\n0\t1\n1\t2\n", "tabs.csv")
    assert read_samples(path)["output"].tolist() == [1.0, 2.0]
    path = _csv(tmp_path, "time [s],output [P]\n0,1\n1,2\n", "commas.txt")
    assert read_samples(path).format == "csv"
    path = _csv(tmp_path, "time [s];output [P]\n0;1\n1;2\n", "semi.csv")
    assert read_samples(path, delimiter=";")["output"].tolist() == [1.0, 2.0]


def test_column_selection(tmp_path):
    path = write_samples_csv(tmp_path / "s.csv", {**_series(20), "temp": np.full(20, 20.5)},
                             {**UNITS, "temp": "degC"})
    table = read_samples(path, columns=["temp", ("output", "P")])
    assert list(table.columns) == ["temp", "output"]
    assert table.units == {"temp": "degC", "output": "P"}


def test_npy_structured_round_trip_is_a_read_only_memory_map(tmp_path):
    data = _series(300)
    path = write_samples_npy(tmp_path / "s.npy", data, {"time": "s", "output": "°/h"})
    table = read_samples(path, expected_interval_s=0.01)
    assert table.format == "npy" and table.n_rows == 300
    assert table.units == {"time": "s", "output": "°/h"}
    for name in data:
        assert np.array_equal(_bits(table[name]), _bits(data[name]))
        assert not table[name].flags.writeable
    assert isinstance(table["output"].base, np.memmap) or not table["output"].flags.owndata
    assert table.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()


def test_plain_npy_needs_declared_columns(tmp_path):
    one = np.arange(10.0)
    np.save(tmp_path / "one.npy", one)
    table = read_samples(tmp_path / "one.npy", columns=[("output", "P")])
    assert table.units == {"output": "P"} and np.array_equal(table["output"], one)
    two = np.column_stack([np.arange(10) * 0.1, np.arange(10, dtype=float) ** 2])
    np.save(tmp_path / "two.npy", two)
    table = read_samples(tmp_path / "two.npy", columns=[("time", "s"), ("output", "LSB")])
    assert np.array_equal(table["output"], two[:,
                                               1]) and table.sample_interval_s == pytest.approx(0.1)
    np.save(tmp_path / "ints.npy", np.arange(5, dtype=np.int32))
    table = read_samples(tmp_path / "ints.npy", columns=[("count", "P")])
    assert table["count"].dtype == np.float64 and table["count"].tolist() == [0, 1, 2, 3, 4]


def test_parquet_units_come_from_column_names(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    data = _series(100)
    tbl = pa.table({"time [s]": data["time"], "output [mV]": data["output"],
                    "count [P]": pa.array(np.arange(100), pa.int32())})
    pq.write_table(tbl, tmp_path / "s.parquet", row_group_size=30)
    table = read_samples(tmp_path / "s.parquet")
    assert table.format == "parquet"
    assert table.units == {"time": "s", "output": "mV", "count": "P"}
    assert np.array_equal(_bits(table["output"]), _bits(data["output"]))
    assert table["count"].tolist() == list(range(100))


def test_min_rows_zero_allows_a_header_only_file(tmp_path):
    table = read_samples(_csv(tmp_path, GOOD_HEAD), min_rows=0)
    assert table.n_rows == 0 and table["time"].shape == (0,)


def test_jittery_time_passes_with_tolerance_off(tmp_path):
    t = np.arange(100) * 0.01 + np.tile([0.0, 1e-4], 50)
    path = write_samples_csv(tmp_path / "j.csv", {"time": t, "output": np.zeros(100)}, UNITS)
    table = read_samples(path, rel_interval_tol=None)
    assert table.sample_interval_s == pytest.approx(0.01, rel=0.02)


def test_chunk_and_block_boundaries(tmp_path, monkeypatch):
    """Small parser blocks and check chunks: errors are still located exactly."""
    monkeypatch.setattr(readers_text, "_BLOCK_BYTES", 1 << 12)
    monkeypatch.setattr(readers_common, "_CHECK_ROWS", 37)
    data = _series(5000, dt=1.0)
    path = write_samples_csv(tmp_path / "b.csv", data, UNITS)
    table = read_samples(path, expected_interval_s=1.0)
    assert np.array_equal(_bits(table["output"]), _bits(data["output"]))
    lines = path.read_text().splitlines()

    def damaged(name: str, row_4001: str) -> Path:
        out = lines.copy()
        out[4001] = row_4001  # data row 4001 (line 4002 before the blank line)
        out.insert(100, "")  # a blank line shifts the line numbers, not the row numbers
        return _csv(tmp_path, "\n".join(out) + "\n", name)

    _expect(damaged("bad.csv", "4000,oops"), ["'oops'", "row 4001 (line 4003)"],
            field="output [P], row 4001")
    _expect(damaged("nan.csv", "4000,nan"), ["NaN", "line 4003"], field="output [P], row 4001")
    _expect(damaged("nu.csv", "4000.5,1"), ["non-uniform", "line 4003"],
            field="time [s], row 4001")
    _expect(damaged("short.csv", "4000"), ["row 4001 (line 4003) has 1 cell(s)"],
            field="row 4001")


# --------------------------------------------------------------------------- bad input


def test_missing_file(tmp_path):
    err = _expect(tmp_path / "nope.csv", ["file not found"])
    assert err.hint


def test_empty_file(tmp_path):
    _expect(_csv(tmp_path, ""), ["empty"])


def test_unknown_suffix(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n", "seg.xls"), ["unknown sample file type", ".csv"])


def test_only_comments_no_header(tmp_path):
    _expect(_csv(tmp_path, "# just a comment\n\n# another\n"), ["no header line"], field="header")


def test_header_that_is_data(tmp_path):
    _expect(_csv(tmp_path, "0,1.5\n1,2.5\n"), ["looks like data"], field="header")


def test_header_not_utf8(tmp_path):
    path = tmp_path / "latin1.csv"
    path.write_bytes("time [s],rate [°/h]\n0,1\n".encode("latin-1"))
    _expect(path, ["not valid UTF-8"], field="header")


def test_header_cell_without_unit(tmp_path):
    err = _expect(_csv(tmp_path, "time [s],output\n0,1\n"), ["has no unit", "[1]"], field="output")
    assert "dimensionless" in err.hint


def test_header_cell_with_empty_unit(tmp_path):
    _expect(_csv(tmp_path, "time [s],output []\n0,1\n"), ["empty unit"], field="output []")


def test_duplicate_column_names(tmp_path):
    _expect(_csv(tmp_path, "time [s],output [P],output [mV]\n0,1,2\n"),
            ["appears twice", "columns 2 and 3"], field="output")


def test_truncated_last_row(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n1,2\n2\n"),
            ["row 3 (line 4) has 1 cell(s) but the header has 2", "truncated"], field="row 3")


def test_file_ending_mid_row(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n1,2\n2,3.1"), ["ends mid-row"], field="line 4")
    # the check can be relaxed for files known to be complete
    assert read_samples(_csv(tmp_path, GOOD_HEAD + "0,1\n1,2", "ok.csv"),
                        require_final_newline=False).n_rows == 2


def test_extra_cell(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n1,2,3\n2,3\n"),
            ["row 2 (line 3) has 3 cell(s) but the header has 2"], field="row 2")


def test_non_numeric_cell(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + _rows([1, 2, 3, 4]) + "4,abc\n5,6\n"),
            ["row 5 (line 6)", "'abc'", "not a number", "column 'output [P]'"],
            field="output [P], row 5")


def test_empty_cell(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n1,\n2,3\n"), ["empty cell"], field="output [P], row 2")


def test_nan(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + _rows([1, 2, "nan", 4])), ["NaN in row 3 (line 4)"],
            field="output [P], row 3")


def test_inf(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + _rows([1, "-inf", 3])), ["-Inf in row 2"],
            field="output [P], row 2")
    _expect(_csv(tmp_path, GOOD_HEAD + _rows([1, "1e999", 3]), "big.csv"), ["+Inf in row 2"],
            field="output [P], row 2")


def test_fewer_rows_than_required(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + _rows([1, 2, 3])), ["3 data row(s)", "10 required"],
            field="rows", min_rows=10)
    _expect(_csv(tmp_path, GOOD_HEAD, "header_only.csv"), ["0 data row(s)"], field="rows")


def test_time_going_backwards(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n1,1\n2,1\n1.5,1\n4,1\n"),
            ["backwards at row 4 (line 5)", "2 in row 3, then 1.5"], field="time [s], row 4")


def test_duplicate_time_stamp(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n1,1\n1,1\n2,1\n"),
            ["duplicate time stamp 1 in rows 2 and 3"], field="time [s], row 3")


def test_gap_in_time(tmp_path):
    t = [0, 1, 2, 3, 4, 7, 8, 9, 10, 11]
    err = _expect(_csv(tmp_path, GOOD_HEAD + "".join(f"{x},1\n" for x in t)),
                  ["gap", "before row 6 (line 7)", "from 4 to 7", "median interval 1"],
                  field="time [s], row 6")
    assert "interpolate" in err.hint


def test_non_uniform_sampling(tmp_path):
    t = [0, 1, 2, 3.01, 4, 5, 6]
    _expect(_csv(tmp_path, GOOD_HEAD + "".join(f"{x},1\n" for x in t)),
            ["non-uniform sampling at row 4"], field="time [s], row 4")


def test_interval_disagrees_with_expected(tmp_path):
    path = write_samples_csv(tmp_path / "i.csv", _series(50, dt=1.0), UNITS)
    _expect(path, ["interval is 1 but 2 was expected"], field="time [s]", expected_interval_s=2.0)


def test_declared_column_missing(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n"), ["'rate' is not in the file", "'output [P]'"],
            field="rate", columns=["rate"])


def test_declared_unit_disagrees(tmp_path):
    _expect(_csv(tmp_path, GOOD_HEAD + "0,1\n"), ["'P'", "'LSB' was declared"],
            field="output [P]", exc=UnitError, columns=[("output", "LSB")])


def test_plain_npy_without_declaration(tmp_path):
    np.save(tmp_path / "p.npy", np.zeros((5, 2)))
    _expect(tmp_path / "p.npy", ["carries no column names or units"], field="columns")
    _expect(tmp_path / "p.npy", ["2 column(s) but 1 were declared"], field="columns",
            columns=[("output", "P")])


def test_npy_nan_and_bad_fields(tmp_path):
    data = _series(50)
    data["output"][17] = np.nan
    np.save(tmp_path / "n.npy", np.rec.fromarrays([data["time"], data["output"]],
                                                   names=["time [s]", "output [P]"]))
    _expect(tmp_path / "n.npy", ["NaN in row 18 (index 17)"], field="output [P], row 18")
    np.save(tmp_path / "f.npy", np.zeros(3, dtype=[("time [s]", "f8"), ("output", "f8")]))
    _expect(tmp_path / "f.npy", ["field name 'output' has no unit"], field="output")


def test_npy_truncated_and_not_npy(tmp_path):
    path = write_samples_npy(tmp_path / "t.npy", _series(100), UNITS)
    path.write_bytes(path.read_bytes()[:-100])
    _expect(path, ["truncated"], field="data")
    _expect(_csv(tmp_path, "hello", "x.npy"), ["not a .npy file"], field="header")


def test_parquet_bad_inputs(tmp_path):
    import pyarrow as pa
    import pyarrow.parquet as pq

    field = pa.field("output", pa.float64(), metadata={b"unit": b"P"})
    pq.write_table(pa.table([pa.array([1.0, 2.0])], schema=pa.schema([field])), tmp_path
                   / "m.parquet")
    err = _expect(tmp_path / "m.parquet", ["has no unit"], field="output")
    assert "metadata" in err.hint
    pq.write_table(pa.table({"output [P]": [1.0, None, 3.0]}), tmp_path / "null.parquet")
    _expect(tmp_path / "null.parquet", ["row 2 (index 1)", "empty"], field="output [P], row 2")
    pq.write_table(pa.table({"output [P]": ["1", "x"]}), tmp_path / "str.parquet")
    _expect(tmp_path / "str.parquet", ["type string"], field="output [P], row 1")
    pq.write_table(pa.table({"output [P]": [1.0, float("inf")]}), tmp_path / "inf.parquet")
    _expect(tmp_path / "inf.parquet", ["+Inf in row 2 (index 1)"], field="output [P], row 2")
    _expect(_csv(tmp_path, "not parquet", "bad.parquet"), ["not a readable parquet file"],
            field="header")


def test_file_changed_while_hashing(tmp_path):
    path = write_samples_csv(tmp_path / "c.csv", _series(10), UNITS)
    key = readers_common.stat_key(path.stat())
    path.write_text(path.read_text() + "# appended\n")
    with pytest.raises(DataError, match="changed while it was being read") as info:
        readers_common.Digest(path, key).result()
    assert str(path) in str(info.value)


# --------------------------------------------------------------------------- writers


def test_writer_is_atomic_and_leaves_no_temp_files(tmp_path):
    path = tmp_path / "w.csv"
    path.write_text("precious\n")
    with pytest.raises(DataError, match="finite"):
        write_samples_csv(path, {"x": np.array([1.0, np.nan])}, {"x": "1"})
    assert path.read_text() == "precious\n"
    write_samples_csv(path, {"x": np.arange(3.0)}, {"x": "1"}, comments=["made by a test"])
    assert path.read_text() == "# made by a test\nx [1]\n0\n1\n2\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.csv"]


def test_writer_rejects_bad_columns(tmp_path):
    path = tmp_path / "w.csv"
    with pytest.raises(DataError, match="no unit given"):
        write_samples_csv(path, {"x": [1.0]}, {})
    with pytest.raises(DataError, match="cannot be written as a header cell"):
        write_samples_csv(path, {"x [s]": [1.0]}, {"x [s]": "s"})
    with pytest.raises(DataError, match="has 1 rows, others 2"):
        write_samples_csv(path, {"x": [1.0, 2.0], "y": [1.0]}, {"x": "1", "y": "1"})
    with pytest.raises(DataError, match="2\\*\\*53"):
        write_samples_csv(path, {"x": np.array([2**60])}, {"x": "1"})
    assert not path.exists()


def test_writer_handles_many_chunks(tmp_path, monkeypatch):
    monkeypatch.setattr(readers_writing, "_WRITE_ROWS", 1000)
    data = _series(12_345, dt=0.001)
    path = write_samples_csv(tmp_path / "many.csv", data, UNITS)
    table = read_samples(path, expected_interval_s=0.001)
    assert np.array_equal(_bits(table["output"]), _bits(data["output"]))


def test_import_is_cheap():
    code = "import sys, metro.instruments.readers; print('pyarrow' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env={**os.environ, "PYTHONWARNINGS": "ignore"})
    assert out.stdout.strip() == "False"


def test_a_campaign_saved_with_a_byte_order_mark_and_crlf_reads_the_same(tmp_path):
    """Windows editors and Excel save UTF-8 with a byte-order mark and CRLF line ends; the manifest
    and its samples then read exactly as the plain files do (the BOM once made the manifest
    'not valid TOML at line 1, column 1')."""
    import shutil

    from metro.core.run.manifest import load_manifest
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    src = Path(__file__).resolve().parents[2] / "docs" / "examples" / "campaign"
    dst = tmp_path / "campaign"
    shutil.copytree(src, dst)
    for f in dst.iterdir():
        text = f.read_text(encoding="utf-8")
        f.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode("utf-8"))
    plain = load_manifest(src / "manifest.toml", pm.reader_for)
    windows = load_manifest(dst / "manifest.toml", pm.reader_for)
    assert plain.device.id == windows.device.id and len(plain.segments) == len(windows.segments)
    for a, b in zip(plain.segments, windows.segments):
        ca, cb = a.columns(), b.columns()
        assert ca.keys() == cb.keys()
        for k in ca:
            assert ca[k][1] == cb[k][1]
            np.testing.assert_array_equal(ca[k][0], cb[k][0])
