"""Cases from Python: dotted paths equal editing the TOML; bad paths and values raise
with the file and the field named; construction from text and dicts."""

from __future__ import annotations

import errno
import re
from pathlib import Path

import pytest

import beamflow
from conftest import REPO, assert_same, tree_contents

FRAME = "cases/beam-frame-12V-60Hz.toml"
CREATED = ("/@created",)


def edited(text: str, pattern: str, repl: str) -> str:
    new, n = re.subn(pattern, repl, text, count=1, flags=re.M)
    assert n == 1, pattern
    return new


def without_case_text(results: beamflow.Results) -> dict:
    """The results without what names the case text as written (its file, its text and
    that text's hash); the resolved case stays."""
    c = tree_contents(results)
    del c["/case/toml"]
    del c["/@"]["case_file"]
    del c["/model@"]["case_hash"]
    return c


def test_dotted_paths_equal_editing_the_toml() -> None:
    text = (REPO / FRAME).read_text()
    assert re.search(r"^x_e = 0\.150?\b", text, re.M), "the case file changed: update this test"
    by_path = beamflow.Case.from_file(FRAME)
    by_path["actuator[0].x_e"] = 0.2
    by_path["actuator[0].voltage.amplitude"] = 9.5
    by_path["damping.zeta"] = 0.02  # not in the file: created, like a sweep does
    text = edited(text, r"^x_e = .*$", "x_e = 0.2")
    text = edited(text, r"^amplitude = .*$", "amplitude = 9.5")
    text = edited(text, r"^\[damping\]\n", "[damping]\nzeta = 0.02\n") if "[damping]" in text else text + "\n[damping]\nzeta = 0.02\n"
    by_text = beamflow.Case.from_toml(text, name=FRAME, base_dir="cases")
    a, b = by_path.run(), by_text.run()
    numbers = assert_same(without_case_text(b), without_case_text(a), ignore=CREATED)
    assert numbers > 1000
    # ... and they differ from the unchanged case (the edit took effect).
    base = beamflow.Case.from_file(FRAME).run()
    assert base.analysis("steady_state").net_power != a.analysis("steady_state").net_power


def test_get_reads_written_values_and_defaults() -> None:
    case = beamflow.Case.from_file(FRAME)
    assert case["actuator[0].type"] == "frame"
    assert case["actuator[0].voltage"]["frequency"] == 60.0
    assert case["beam.youngs_modulus"] == 210e9  # default, not written in the file
    assert "beam.mesh.elements" in case and "beam.nonsense" not in case
    assert case.get("beam.nonsense", 7) == 7
    with pytest.raises(beamflow.FieldNotFound) as e:
        case["beam.nonsense"]
    assert isinstance(e.value, KeyError) and e.value.field == "beam.nonsense" and e.value.file == FRAME
    assert case.get("actuator[0].m_t") is None  # a field of inertial actuators only, unset here


@pytest.mark.parametrize(
    "path, value, field, reason",
    [
        ("actuator[0].x_e", 0.9, "actuator[0].x_e", "outside the beam"),
        ("actuator[0].x_e", float("nan"), "actuator[0].x_e", ""),
        ("beam.mesh.elements", 0, "beam.mesh.elements", ""),
        ("damping.zeta", -0.1, "damping.zeta", ""),
        ("actuator[0].x_ee", 0.2, "actuator[0].x_ee", "unknown field `x_ee`"),
        ("actuator[1].x_e", 0.2, "actuator[1].x_e", "the case has 1 entries in `actuator`"),
        ("actuator[x].x_e", 0.2, "actuator[x].x_e", "index"),
        ("actuator[0].x_e", "far", "actuator[0].x_e", "invalid type"),
        ("beam", 3.0, "beam", "invalid type"),
    ],
)
def test_bad_paths_and_values_raise_with_the_field_and_change_nothing(path, value, field, reason) -> None:
    case = beamflow.Case.from_file(FRAME)
    before = case.to_toml()
    with pytest.raises(beamflow.InputError) as e:
        case[path] = value
    assert e.value.file == FRAME
    assert e.value.field == field, str(e.value)
    assert reason in e.value.reason
    assert f"`{field}`" in str(e.value)
    assert case.to_toml() == before


def test_unsupported_python_values_raise_type_error() -> None:
    case = beamflow.Case.from_file(FRAME)
    with pytest.raises(TypeError, match="cannot put"):
        case["actuator[0].x_e"] = object()
    with pytest.raises(TypeError):
        case["actuator[0].x_e"] = None


def test_update_checks_once_after_all_changes() -> None:
    case = beamflow.Case.from_file(FRAME)
    # A shorter beam only fits if the actuator moves first; each alone is invalid.
    with pytest.raises(beamflow.InputError):
        case["beam.length"] = 0.1
    case.update({"beam.length": 0.4, "actuator[0].x_e": 0.2})
    assert case["beam.length"] == 0.4 and case["actuator[0].x_e"] == 0.2
    with pytest.raises(beamflow.InputError) as e:
        case.update([("beam.length", 0.3), ("actuator[0].x_e", 0.35)])
    assert case["beam.length"] == 0.4  # unchanged after a failed update
    assert e.value.file == FRAME


def test_integral_floats_set_integer_fields() -> None:
    import numpy as np

    case = beamflow.Case.from_file(FRAME)
    case["beam.mesh.elements"] = np.float64(120.0)
    assert case["beam.mesh.elements"] == 120 and isinstance(case["beam.mesh.elements"], int)
    with pytest.raises(beamflow.InputError, match="beam.mesh.elements"):
        case["beam.mesh.elements"] = 120.5
    assert case.check()["elements"] == 120


def test_from_dict_equals_from_toml() -> None:
    d = {
        "title": "inertial on the paper beam",
        "actuator": [{"type": "inertial", "x_e": 0.15, "voltage": {"kind": "sine", "amplitude": 12.0, "frequency": 60.0}}],
        "analysis": [{"type": "steady_state", "harmonics": 5}],
    }
    a = beamflow.Case.from_dict(d)
    b = beamflow.Case.from_toml(a.to_toml(), name="<dict>")
    assert a.to_dict() == d
    assert a.to_dict(defaults=True)["beam"]["length"] == 0.73
    assert_same(tree_contents(a.run()), tree_contents(b.run()), ignore=CREATED)
    assert a.copy()["actuator[0].x_e"] == 0.15


def test_copy_is_independent() -> None:
    a = beamflow.Case.from_file(FRAME)
    b = a.copy()
    b["actuator[0].x_e"] = 0.3
    assert a["actuator[0].x_e"] == 0.15 and b["actuator[0].x_e"] == 0.3
    assert a.to_toml() == (REPO / FRAME).read_text()  # unchanged: the file's own text


def test_construction_errors_name_the_file() -> None:
    with pytest.raises(beamflow.ParseError) as e:
        beamflow.Case.from_toml("[beam\nlength = 1", name="broken.toml")
    assert e.value.file == "broken.toml" and "line 1" in e.value.message
    with pytest.raises(beamflow.InputError) as e:
        beamflow.Case.from_dict({"beam": {"length": -1.0}}, name="neg")
    assert (e.value.file, e.value.field) == ("neg", "beam.length")
    with pytest.raises(beamflow.IoError) as e:
        beamflow.Case.from_file("cases/absent.toml")
    assert isinstance(e.value, OSError) and e.value.errno == errno.ENOENT and "absent.toml" in e.value.path
    with pytest.raises(beamflow.InputError, match="did you mean `length`") as e:
        beamflow.Case.from_toml("[beam]\nlenght = 0.5\n")
    assert e.value.field == "beam.lenght" and "line 2" in e.value.reason
    with pytest.raises(beamflow.InputError, match="unknown field") as e:
        beamflow.Case.from_dict({"actuator": [{"type": "inertial", "x_e": 0.1, "voltage": {"kind": "sine", "amplitud": 1}}]})
    assert e.value.field == "actuator[0].voltage.amplitud"


def test_check_reports_the_model() -> None:
    info = beamflow.Case.from_file(FRAME).check()
    assert info["actuators"] == ["frame"]
    assert info["links"] == ["frame_stack", "frame_left_leg", "frame_right_leg"]
    assert info["dofs"] == 2 * (info["elements"] + 1) - 4 + 2  # clamped ends; frame body y, phi


def test_relative_paths_resolve_next_to_the_case(tmp_path: Path) -> None:
    case = beamflow.Case.from_file(FRAME)
    assert case.base_dir == Path("cases")
    moved = beamflow.Case.from_toml(case.to_toml(), name="copy", base_dir=tmp_path)
    assert moved.base_dir == tmp_path
