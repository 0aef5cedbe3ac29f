"""tennislab.io.files: output paths checked before the work, atomic writes with the user's umask, safe names."""

from __future__ import annotations

import os
import stat

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.errors import InputError
from tennislab.io.files import (
    atomic_write,
    check_output_dir,
    check_output_path,
    current_umask,
    new_file_mode,
    safe_basename,
)


def one_line(exc) -> str:
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


def test_a_good_path_is_returned(tmp_path):
    p = tmp_path / "fig.png"
    assert check_output_path("plot", p, (".png",)) == str(p)
    assert check_output_path("plot", str(tmp_path / "FIG.PNG"), (".png",)) == str(tmp_path / "FIG.PNG")
    p.write_text("old")  # an existing file is replaced, not refused
    assert check_output_path("plot", str(p)) == str(p)


@pytest.mark.parametrize(
    "make,expect",
    [
        (lambda d: d / "file.txt" / "x.png", "is a file, not a directory"),
        (lambda d: d / "file.txt" / "sub" / "x.png", "is a file, not a directory"),
        (lambda d: d / "missing" / "x.png", "does not exist"),
        (lambda d: d / ("a" * 300 + ".png"), "304 characters long (limit 255 bytes)"),
        (lambda d: d / "x.xyz", "unsupported file type ('.xyz')"),
        (lambda d: d / "noext", "unsupported file type (no extension)"),
        (lambda d: d, "is a directory"),
        (lambda d: str(d) + "/", "is a directory"),
        (lambda d: "", "empty"),
        (lambda d: str(d / "a\x00b.png"), "NUL"),
    ],
)
def test_bad_output_paths_are_one_line_errors_naming_the_parameter(tmp_path, make, expect):
    (tmp_path / "file.txt").write_text("mine")
    with pytest.raises(InputError) as e:
        check_output_path("plot", make(tmp_path), (".png", ".pdf"))
    msg = one_line(e)
    assert msg.startswith("plot: ") and expect in msg, msg
    assert sorted(os.listdir(tmp_path)) == ["file.txt"]  # nothing created


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes anywhere")
def test_a_read_only_directory_is_refused(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        with pytest.raises(InputError, match="not writable"):
            check_output_path("csv", ro / "x.csv")
    finally:
        ro.chmod(0o755)


def test_output_directories(tmp_path):
    (tmp_path / "file").write_text("x")
    assert check_output_dir("out_dir", tmp_path) == str(tmp_path)
    assert check_output_dir("out_dir", tmp_path / "new" / "deeper") == str(tmp_path / "new" / "deeper")
    assert not (tmp_path / "new").exists()  # checked, not created
    for bad, expect in [
        (tmp_path / "file", "is a file, expected a directory"),
        (tmp_path / "file" / "sub", "is a file, not a directory"),
        (tmp_path / "new", None),
    ]:
        if expect is None:
            with pytest.raises(InputError, match="does not exist"):
                check_output_dir("out_dir", bad, create=False)
            continue
        with pytest.raises(InputError) as e:
            check_output_dir("out_dir", bad)
        assert one_line(e).startswith("out_dir: ") and expect in str(e.value)
    with pytest.raises(InputError, match="characters long"):
        check_output_dir("out_dir", tmp_path / ("d" * 300))


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o002])
def test_atomic_writes_use_the_users_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        assert current_umask() == umask
        p = tmp_path / "out.csv"
        atomic_write(str(p), lambda fh: fh.write("a,b\n"))
        assert stat.S_IMODE(p.stat().st_mode) == 0o666 & ~umask == new_file_mode()
        assert p.read_text() == "a,b\n"
    finally:
        os.umask(old)


def test_nothing_half_written_on_failure(tmp_path):
    p = tmp_path / "keep.txt"
    p.write_text("original")

    def boom(fh):
        fh.write("half")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError):
        atomic_write(str(p), boom)
    assert p.read_text() == "original" and os.listdir(tmp_path) == ["keep.txt"]
    with pytest.raises(RuntimeError):
        atomic_write(str(tmp_path / "new.txt"), boom)
    assert os.listdir(tmp_path) == ["keep.txt"]


@pytest.mark.parametrize(
    "name,safe",
    [
        ("../../etc/passwd", "passwd"),
        ("/abs/path/drill.yaml", "drill.yaml"),
        ("..\\..\\win.yaml", "win.yaml"),
        ("...", "output"),
        ("", "output"),
        (".hidden.yaml", "hidden.yaml"),
        ("a b.yaml", "a b.yaml"),
        ("rm -rf $(x);.yaml", "rm -rf _x_.yaml"),
        ("line\nbreak.yaml", "line_break.yaml"),
        ("CON.yaml", "_CON.yaml"),
        ("Übung 1.yaml", "Übung 1.yaml"),
    ],
)
def test_safe_basename_examples(name, safe):
    assert safe_basename(name) == safe


def test_safe_basename_keeps_the_extension_when_cutting():
    s = safe_basename("x" * 400 + ".yaml")
    assert s.endswith(".yaml") and len(s.encode()) == 200


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=400))
def test_safe_basename_is_always_a_plain_visible_name(name):
    s = safe_basename(name)
    assert s and "/" not in s and "\\" not in s and "\x00" not in s
    assert not s.startswith(".") and s not in (".", "..")
    assert len(s.encode("utf-8")) <= 200
    assert all(ch.isprintable() for ch in s)


def test_read_text_refuses_a_file_over_its_limit_instead_of_cutting_it(tmp_path):
    from tennislab.io.files import read_text

    p = tmp_path / "s.toml"
    p.write_text("e = 0.8\nmu = 0.6\n" + "#" * 100)
    assert read_text(str(p), 200).startswith("e = 0.8")
    with pytest.raises(InputError, match=r"s.toml: larger than 50 bytes"):
        read_text(str(p), 50)


@pytest.mark.parametrize(
    "text,frag", [("a = " + "[" * 100_000, "nested too deeply|not valid TOML"), ("a = " + "9" * 5000, "not valid TOML")]
)
def test_toml_nesting_and_huge_integers_are_one_line(tmp_path, text, frag):
    from tennislab.io.config import read_toml

    p = tmp_path / "c.toml"
    p.write_text(text)
    with pytest.raises(InputError, match=frag) as exc:
        read_toml(str(p))
    assert "\n" not in str(exc.value)


def test_surface_file_over_its_limit_is_refused(tmp_path):
    from tennislab.io.surface_file import MAX_BYTES, read_surface

    p = tmp_path / "big.toml"
    p.write_text("e = 0.8\nmu = 0.6\n" + "#" * MAX_BYTES)
    with pytest.raises(InputError, match="larger than"):
        read_surface(str(p))
