"""dynamap.Mapper, fed one scan at a time, makes the S, D and object table of dynamap.map() on
the same scans and poses; malformed scans and configurations are errors."""

import numpy as np
import pytest

import dynamap
from conftest import bundled


@pytest.mark.parametrize("log", ["tiny", "people"])
def test_scan_by_scan_equals_the_whole_run(log, exe):
    whole = dynamap.map(bundled(log), poses="ground_truth")
    m = dynamap.Mapper()
    inserted = 0
    for s in dynamap.scans(bundled(log), poses="ground_truth"):
        inserted += m.add(s["ranges"], s["angles"], s["pose"], s["t"], max_range=s["max_range"],
                          mount=s["mount"], valid=s["valid"])
    assert inserted == whole.summary["scans"]["used"] == m.counts["used"]
    assert m.origin == pytest.approx(whole.origin) and m.resolution == whole.resolution
    assert np.array_equal(m.static, whole.static)
    assert np.array_equal(m.dynamic, whole.dynamic)
    assert m.objects.equals(whole.objects) if hasattr(m.objects, "equals") else \
        m.objects == whole.objects
    assert len(m.events) == len(whole.events)


def test_a_scan_of_its_own_makes_cells_where_it_says():
    m = dynamap.Mapper()
    angles = np.linspace(-np.pi / 2, np.pi / 2, 181)
    ranges = np.full(181, 3.0, dtype=np.float32)  # a half circle of wall 3 m around the robot
    # The robot in the middle of a cell, so that each beam ends inside one.
    for k in range(10):
        assert m.add(ranges, angles, (1.02, 2.02, 0.0), t=k * 0.1)
    s, (x0, y0), res = m.static, m.origin, m.resolution

    def p(x, y):
        return s[int((y - y0) / res), int((x - x0) / res)]

    assert p(1.02 + 3.0, 2.02) > 0.5  # the wall ahead
    assert p(1.02 + 1.5, 2.02) < 0.1  # free space before it
    assert p(1.02, 2.02 + 3.0) > 0.5  # the wall to the left (beam at +90 degrees)
    assert p(1.02, 2.02 - 3.0) > 0.5  # and to the right
    assert p(1.02 - 2.0, 2.02) == pytest.approx(0.5)  # behind the laser: never seen
    # Angles the other way round are the same fan (its beams inserted in the other order).
    m2 = dynamap.Mapper()
    for k in range(10):
        m2.add(ranges[::-1], angles[::-1], (1.02, 2.02, 0.0), t=k * 0.1)
    assert np.mean(m2.static != s) < 0.001
    assert m2.static[int((2.02 - y0) / res), int((4.02 - x0) / res)] > 0.5


def test_malformed_scans_are_value_errors(tmp_path):
    m = dynamap.Mapper()
    with pytest.raises(ValueError, match="differ in length"):
        m.add(np.ones(10), np.linspace(0, 1, 11), (0, 0, 0))
    with pytest.raises(ValueError, match="beam 3 is not evenly spaced"):
        m.add(np.ones(5), [0.0, 0.1, 0.2, 0.35, 0.4], (0, 0, 0))
    with pytest.raises(ValueError, match="max_range"):
        m.add(np.ones(5), np.linspace(0, 1, 5), (0, 0, 0), max_range=0)
    assert m.counts["used"] == 0
    bad = tmp_path / "bad.ini"
    bad.write_text("[objects]\nno_such_key = 2\n")
    with pytest.raises(dynamap.ConfigError, match="no_such_key"):
        dynamap.Mapper(str(bad))
    with pytest.raises(dynamap.InputError):
        dynamap.scans(str(tmp_path / "missing.rawlog"))
