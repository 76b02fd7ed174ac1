"""Hostile YAML files: the core reader (designlab.yamlio) and the study loader refuse them clearly.

What a plain ``yaml.safe_load(open(path).read())`` does with them: ``/dev/zero`` fills the
memory, a FIFO blocks forever, a NUL byte or a 5,000-digit integer is a traceback, a key
written twice is silently overwritten. Each must be a :class:`~designlab.yamlio.YamlError`
(a ``StudyError`` for a study) naming the file and, where the text has one, the line.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from designlab.errors import DesignlabError, StudyError
from designlab.study import load_study
from designlab.yamlio import (
    MAX_BYTES,
    MAX_DEPTH,
    MAX_NUMBER_CHARS,
    YamlError,
    load_yaml,
    load_yaml_file,
    read_text_file,
)

STUDY = """designlab: 1
kind: impact_cases
name: t
cases:
  - robot: {{mass: {mass}, stiffness: 20e3, damping: 250}}
    foam: FOAM_1
    head: TEST_HEAD
    impact_velocity: 1.25
"""


def test_a_device_is_refused_without_reading_it() -> None:
    with pytest.raises(YamlError, match=r"^/dev/zero: is a character device, not a regular"):
        read_text_file("/dev/zero")
    with pytest.raises(StudyError, match=r"^/dev/zero: is a character device"):
        load_study("/dev/zero")


def test_a_fifo_is_refused_and_never_blocks(tmp_path: Path) -> None:
    fifo = tmp_path / "study.yaml"
    os.mkfifo(fifo)
    outcome: list[BaseException] = []

    def read() -> None:
        try:
            load_study(fifo)
        except BaseException as exc:
            outcome.append(exc)

    worker = threading.Thread(target=read, daemon=True)
    worker.start()
    worker.join(10)
    if worker.is_alive():  # unblock the reader before failing
        with open(fifo, "w"):
            pass
        pytest.fail("reading a FIFO blocked")
    assert isinstance(outcome[0], StudyError), outcome
    assert "is a FIFO (named pipe), not a regular file" in str(outcome[0])
    assert str(outcome[0]).startswith(str(fifo))


def test_a_directory_and_a_missing_file_are_named(tmp_path: Path) -> None:
    with pytest.raises(YamlError, match="is a directory"):
        read_text_file(tmp_path)
    with pytest.raises(StudyError, match=r"nope.yaml: study file not found"):
        load_study(tmp_path / "nope.yaml")


def test_a_file_over_the_cap_is_refused_after_reading_at_most_the_cap(tmp_path: Path) -> None:
    big = tmp_path / "big.yaml"
    big.write_bytes(b"#" * 1000 + b"\n")
    assert read_text_file(big, max_bytes=1001).startswith("#")
    with pytest.raises(YamlError, match=r"larger than 1,000 bytes"):
        read_text_file(big, max_bytes=1000)
    with big.open("wb") as f:  # a sparse file just over the default cap
        f.truncate(MAX_BYTES + 1)
    with pytest.raises(StudyError, match=r"big.yaml: the file is larger than 5,000,000 bytes"):
        load_study(big)


def test_not_utf8_names_the_line(tmp_path: Path) -> None:
    f = tmp_path / "s.yaml"
    f.write_bytes(b"designlab: 1\nname: \xff\n")
    with pytest.raises(StudyError, match=r"s.yaml:2: not UTF-8 text"):
        load_study(f)


def test_a_nul_byte_is_a_clear_error_with_its_line(tmp_path: Path) -> None:
    f = tmp_path / "s.yaml"
    f.write_text(STUDY.format(mass=9.6).replace("name: t", "name: t\x00u"), encoding="utf-8")
    with pytest.raises(StudyError, match=r"s.yaml:3: a NUL byte at character \d+"):
        load_study(f)
    with pytest.raises(YamlError, match=r"^x.yaml:2: the control character #x0007"):
        load_yaml("a: 1\nb: \x07\n", file="x.yaml")


@pytest.mark.parametrize("digits", [MAX_NUMBER_CHARS + 1, 5000])
def test_a_number_of_thousands_of_digits_is_a_clear_error(tmp_path: Path, digits: int) -> None:
    f = tmp_path / "s.yaml"
    f.write_text(STUDY.format(mass="9" * digits), encoding="utf-8")
    head = r"s.yaml:5: cases\[0\].robot.mass: the number 999999999999\.\.\.9999 is"
    with pytest.raises(StudyError, match=head) as err:
        load_study(f)
    assert f"written with {digits:,} characters" in str(err.value)
    raw = r"^the number 111111111111\.\.\.11\.5 is not allowed"
    with pytest.raises(YamlError, match=raw) as info:
        load_yaml(f"a: {'1' * digits}.5\n")
    assert info.value.line == 1 and info.value.path == ("a",)


def test_numbers_within_the_cap_still_load() -> None:
    assert load_yaml(f"a: {'9' * 19}\nb: 1.7976931348623157e308\n")[0] == {
        "a": int("9" * 19),
        "b": 1.7976931348623157e308,
    }


@pytest.mark.parametrize(
    ("text", "key", "lines"),
    [
        ("a: 1\nb: 2\na: 3\n", "a", (1, 3)),
        ("a: 1\n'a': 2\n", "a", (1, 2)),
        ("m:\n  x: 1\n  y: 2\n  x: 3\n", "x", (2, 4)),
        ("1: a\n01: b\n", "01", (1, 2)),  # the same key once loaded (the int 1)
        ("- {k: 1, k: 2}\n", "k", (1, 1)),
    ],
)
def test_a_repeated_key_is_refused_naming_the_key_and_both_lines(
    text: str, key: str, lines: tuple[int, int]
) -> None:
    with pytest.raises(YamlError) as info:
        load_yaml(text, file="r.yaml")
    message = str(info.value)
    assert message.startswith(f"r.yaml:{lines[1]}: "), message
    assert f"key {key!r} appears twice in the same mapping, on lines {lines[0]} and {lines[1]}" in (
        message
    )


def test_raw_yaml_errors_are_wrapped_with_file_and_line(tmp_path: Path) -> None:
    f = tmp_path / "room.yaml"
    f.write_text("goal: [1, 2\nstart: [0, 0]\n", encoding="utf-8")
    with pytest.raises(YamlError, match=r"^.*room.yaml:\d: YAML syntax error: ") as info:
        load_yaml_file(f)
    assert isinstance(info.value, DesignlabError) and isinstance(info.value, ValueError)
    with pytest.raises(YamlError, match=r"^x.yaml:1: cannot read the value '2020-13-45'"):
        load_yaml("a: 2020-13-45\n", file="x.yaml")
    with pytest.raises(YamlError, match=r"^x.yaml:2: cannot read the value 'abc'"):
        load_yaml("a: 1\nb: !!float abc\n", file="x.yaml")


def test_deep_nesting_is_refused_with_its_line() -> None:
    with pytest.raises(YamlError, match=rf"more than {MAX_DEPTH} levels deep") as info:
        load_yaml("a: " + "[" * 5000 + "]" * 5000 + "\n", file="d.yaml")
    assert str(info.value).startswith("d.yaml:1: ")


def test_a_symlink_to_a_regular_file_is_read(tmp_path: Path) -> None:
    f = tmp_path / "s.yaml"
    f.write_text(STUDY.format(mass=9.6), encoding="utf-8")
    link = tmp_path / "link.yaml"
    link.symlink_to(f)
    assert load_study(link).name == "t"


@pytest.mark.parametrize(
    ("value", "shown"),
    [("[1, 2]", "(got a list: [1, 2])"), ("{a: 1}", "(got a mapping: {'a': 1})"),
     ("[]", "(got an empty list [])")],
)  # fmt: skip
def test_a_list_or_mapping_for_a_number_names_what_was_given(value: str, shown: str) -> None:
    from designlab.study import parse_study

    text = STUDY.format(mass=9.6).replace("impact_velocity: 1.25", f"impact_velocity: {value}")
    with pytest.raises(StudyError) as info:
        parse_study(text, file="s.yaml")
    assert str(info.value).startswith("s.yaml:8: cases[0].impact_velocity: Input should be a valid")
    assert shown in str(info.value)


def test_a_density_no_area_can_hold_is_named_as_the_density() -> None:
    from designlab.study import parse_study

    text = (
        "designlab: 1\nkind: navigation_crowds\nname: c\nscenarios: [corridor_counterflow]\n"
        "densities: [0.1, 1.0e-300]\nseeds: [0]\nmethods: [{method: vff}]\n"
        "crowd: {length: 8.0, horizon: 0.5}\n"
    )
    with pytest.raises(StudyError, match=r"^c.yaml:5: densities\[1\]: corridor_counterflow at "
                       r"1e-300/m\^2: density = 1e-300 1/m\^2 is not allowed"):  # fmt: skip
        parse_study(text, file="c.yaml")
