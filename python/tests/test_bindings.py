"""dynamap.map() against `dynamap map`: every summary.json figure, S and D cell by cell against
the grid files, the tables and poses, the command's errors and warnings, the GIL."""

import glob
import os
import shutil
import tempfile
import threading
import time

import numpy as np
import pytest

import dynamap
from dynamap import _tables
from conftest import bundled, run_cli, summary_of

LOGS = ["tiny", "people", "walkers"]


@pytest.fixture(scope="module", params=LOGS)
def pair(request, tmp_path_factory, exe):
    """The same log mapped by the command and by dynamap.map(), each into its own folder."""
    log = bundled(request.param)
    cli_out = str(tmp_path_factory.mktemp("cli"))
    status, err = run_cli("--input", log, "--out", cli_out)
    assert status == 0, err
    py_out = str(tmp_path_factory.mktemp("py"))
    return cli_out, dynamap.map(log, out=py_out), py_out


def test_every_summary_figure_equals_the_commands(pair):
    cli_out, r, _ = pair
    expected = summary_of(cli_out)
    got = dict(r.summary)
    got.pop("timing")
    assert got == expected
    assert r.pose_source == expected["pose_source"]


def test_summary_figures_are_those_of_the_arrays_and_tables(pair):
    _, r, _ = pair
    s = r.summary
    rows, cols = r.static.shape
    assert s["map"]["size_cells"] == [cols, rows]
    assert r.dynamic.shape == r.static.shape
    assert s["map"]["x_min"] == pytest.approx(r.origin[0], abs=1e-5)
    assert s["map"]["y_min"] == pytest.approx(r.origin[1], abs=1e-5)
    assert s["map"]["x_max"] == pytest.approx(r.origin[0] + cols * r.resolution, abs=1e-4)
    assert s["map"]["resolution_m"] == pytest.approx(r.resolution, abs=1e-7)
    assert s["cells"]["static_occupied"] == int((r.static > 0.5).sum())
    assert s["cells"]["static_free"] == int((r.static < 0.1).sum())
    assert s["cells"]["dynamic_occupied"] == int((r.dynamic > 0.85).sum())
    assert s["scans"]["read"] == len(r.poses)
    assert s["objects"]["total"] == len(r.objects)
    people = r.people["person_id"] if hasattr(r.people, "columns") else [p["person_id"] for p in r.people]
    assert s["people"]["tracks"] == len(set(people))
    assert r.poses.shape[1] == 4
    assert s["scans"]["first_t"] == pytest.approx(r.poses[0, 0], abs=1e-6)


def test_arrays_equal_the_grid_files_cell_by_cell(pair):
    _, r, py_out = pair
    for name, grid in (("static", r.static), ("dynamic", r.dynamic)):
        f = dynamap.load_gridmap(os.path.join(py_out, name + ".gridmap.gz"))
        assert f["map"].dtype == np.float32 and grid.dtype == np.float32
        assert np.array_equal(f["map"], grid), name
        assert f["origin"] == pytest.approx(r.origin)
        assert f["resolution"] == r.resolution
    assert ((r.static > 0.5).sum() > 100) and ((r.static < 0.1).sum() > 100)


def test_outputs_equal_the_commands_byte_for_byte(pair):
    cli_out, _, py_out = pair
    names = sorted(os.listdir(cli_out))
    assert names == sorted(os.listdir(py_out))
    for n in names:
        if n == "summary.json":
            continue
        with open(os.path.join(cli_out, n), "rb") as a, open(os.path.join(py_out, n), "rb") as b:
            assert a.read() == b.read(), n


def test_tables_are_dataframes_or_lists_of_dicts(pair, monkeypatch):
    _, r, py_out = pair
    pd = pytest.importorskip("pandas")
    assert isinstance(r.objects, pd.DataFrame)
    assert list(r.events.columns) == ["t", "scan_index", "object_id", "event", "cx", "cy",
                                      "size_m", "from_id"]
    monkeypatch.setattr(_tables, "_pd", None)
    rows = dynamap.read_table(os.path.join(py_out, "objects.csv"))
    assert isinstance(rows, list) and len(rows) == len(r.objects)
    for row, (_, frame_row) in zip(rows, r.objects.iterrows()):
        assert row["id"] == frame_row["id"] and isinstance(row["id"], int)
        assert row["size_m"] == pytest.approx(frame_row["size_m"])


def test_a_temporary_output_folder_is_removed(exe):
    before = set(glob.glob(os.path.join(tempfile.gettempdir(), "dynamap-*")))
    r = dynamap.map(bundled("tiny"))
    assert r.out is None and r.static.size > 0 and len(r.poses) > 0
    assert set(glob.glob(os.path.join(tempfile.gettempdir(), "dynamap-*"))) == before


def test_a_session_continued_from_a_prior_reports_its_changes_as_the_command_does(tmp_path, exe):
    first = tmp_path / "first"
    dynamap.map(bundled("tiny"), out=first)
    r = dynamap.map(bundled("tiny"), out=tmp_path / "again", prior=first)
    status, err = run_cli("--input", bundled("tiny"), "--out", str(tmp_path / "cli"),
                          "--prior", str(first))
    assert status == 0, err
    with open(tmp_path / "cli" / "changes.csv") as f:
        expected = _tables.parse_table(f.read())
    assert list(r.changes.columns) == list(expected.columns)
    assert len(r.changes) == len(expected)
    assert r.summary["changes"]["session"] == 2
    assert dynamap.map(bundled("tiny")).changes is None
    with pytest.raises(dynamap.UsageError, match="--initial-pose: only with --prior"):
        dynamap.map(bundled("tiny"), initial_pose=(0, 0, 0))


def _cli_error(*args):
    status, err = run_cli(*args)
    return status, err.strip().splitlines()[-1]


def test_errors_carry_the_commands_message(tmp_path, exe):
    bad_ini = tmp_path / "bad.ini"
    bad_ini.write_text("[map]\nno_such_key = 1\n")
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    cases = [
        (dynamap.InputError, dict(input=str(tmp_path / "missing.rawlog"))),
        (dynamap.UsageError, dict(input=bundled("tiny"), poses="nonsense")),
        (dynamap.ConfigError, dict(input=bundled("tiny"), config=str(bad_ini))),
        (dynamap.Error, dict(input=bundled("tiny"), out=str(a_file / "sub"))),
    ]
    for kind, kw in cases:
        out = kw.pop("out", str(tmp_path / "out"))
        args = dynamap._map.map_args(out=out, **kw)
        status, line = _cli_error(*args)
        with pytest.raises(kind) as e:
            dynamap.map(out=out, **kw)
        assert str(e.value) == line
        assert e.value.exit_status == status
    with pytest.raises(TypeError):
        dynamap.map(bundled("tiny"), no_such_option=1)


def test_a_log_ending_in_a_fault_warns_as_the_command_does(tmp_path, exe):
    cut = tmp_path / "cut.rawlog"
    with open(bundled("tiny"), "rb") as f:
        data = f.read()
    cut.write_bytes(data[: len(data) // 2])
    status, err = run_cli("--input", str(cut), "--out", str(tmp_path / "cli"))
    assert status == 4
    cli_warnings = [l.split("warning: ", 1)[1] for l in err.splitlines() if "warning: " in l]
    with pytest.warns(dynamap.DynamapWarning) as w:
        r = dynamap.map(str(cut), out=str(tmp_path / "py"))
    assert [str(x.message) for x in w] == cli_warnings
    assert r.fault and r.fault in cli_warnings[-1]
    assert r.summary["complete_input"] is False
    assert 0 < len(r.poses) < len(dynamap.map(bundled("tiny")).poses)


def test_the_gil_is_released_while_mapping(exe):
    ticks = []
    done = threading.Event()
    result = {}

    def work():
        result["r"] = [dynamap.map(bundled(log)) for log in ("walkers", "arena")]
        done.set()

    t = threading.Thread(target=work)
    start = time.monotonic()
    t.start()
    while not done.is_set():
        ticks.append(time.monotonic())
        time.sleep(0.01)
    t.join()
    took = time.monotonic() - start
    gaps = np.diff([start] + ticks + [time.monotonic()])
    assert took > 0.5, "the runs are too short to tell"
    # Holding the GIL for a run would leave this thread one gap as long as that run.
    assert gaps.max() < 0.2 * took, (gaps.max(), took)
    assert all(len(r.poses) > 0 for r in result["r"])
