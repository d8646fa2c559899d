"""Tests for eigenupdate.measure.frf (the FRF type, unit conversion) and io.frf_csv."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from _synth import viscous_sdof
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from eigenupdate.errors import InputError
from eigenupdate.io.atomic import atomic_write
from eigenupdate.io.frf_csv import read_frf_csv, write_frf_csv
from eigenupdate.measure.frf import FRF, check_same_axis, dof_label, is_uniform, to_receptance

# Analytic viscously damped SDOF: m x'' + c x' + k x = F.
M, K, C = 2.0, 8.0e4, 12.0


def sdof_receptance(f_hz: np.ndarray) -> np.ndarray:
    return viscous_sdof(f_hz, M, K, C)


def make_frf(n: int = 8, **kw) -> FRF:
    f = np.arange(1, n + 1) * 0.5
    return FRF(f, sdof_receptance(f), **kw)


# ----------------------------------------------------------------------------- FRF


def test_frf_copies_and_freezes_arrays():
    f = np.array([1.0, 2.0, 3.0])
    h = np.array([1.0, 2.0, 3.0])  # real input is stored as complex
    frf = FRF(f, h, (5, -3), (1, 4))
    f[0] = 99.0
    assert frf.frequency_hz[0] == 1.0
    assert frf.receptance.dtype == np.complex128
    assert frf.response == (5, -3) and frf.reference == (1, 4)
    with pytest.raises(ValueError):
        frf.frequency_hz[0] = 0.0
    with pytest.raises(AttributeError):
        frf.source = "x"  # type: ignore[misc]
    assert repr(frf) == "FRF(n=3, 1..3 Hz, response=5-Z, reference=1+RX)"


def test_frf_allows_nan_receptance_and_zero_frequency():
    frf = FRF([0.0, 1.0], [np.nan, 1.0])
    assert np.isnan(frf.receptance[0])


@pytest.mark.parametrize(
    ("freq", "rec", "field", "text"),
    [
        ([1.0, 1.0, 2.0], [1, 1, 1], "frequency_hz", "not strictly increasing"),
        ([2.0, 1.0], [1, 1], "frequency_hz", "not strictly increasing"),
        ([-1.0, 1.0], [1, 1], "frequency_hz", "negative"),
        ([0.0, np.inf], [1, 1], "frequency_hz", "non-finite"),
        ([[1.0, 2.0]], [[1, 1]], "frequency_hz", "1-D"),
        ([], [], "frequency_hz", "non-empty"),
        ([1.0, 2.0], [1, 1, 1], "receptance", "does not match"),
        ([1.0, 2.0], [1, np.inf], "receptance", "infinite"),
        (["a", "b"], [1, 1], "frequency_hz", "not numeric"),
    ],
)
def test_frf_validation(freq, rec, field, text):
    with pytest.raises(InputError, match=text) as info:
        FRF(freq, rec, source="meas.uff")
    assert info.value.field == field
    assert str(info.value).startswith("meas.uff: ")


@pytest.mark.parametrize("dof", [(1, 7), (1, -7), (1.5, 1), (1,), "ab"])
def test_frf_rejects_bad_dof(dof):
    with pytest.raises(InputError, match="response"):
        FRF([1.0], [1.0], dof, (1, 1))


def test_dof_label_and_is_uniform():
    assert dof_label((12, 3)) == "12+Z"
    assert dof_label((3, -6)) == "3-RZ"
    assert is_uniform(np.linspace(0.0, 1000.0, 4001))
    assert not is_uniform(np.array([0.0, 1.0, 2.5]))
    assert is_uniform(np.array([3.0])) and is_uniform(np.array([3.0, 4.0]))


# ----------------------------------------------------------------------------- to_receptance


def test_to_receptance_sdof_mobility_and_accelerance():
    f = np.linspace(0.0, 60.0, 601)
    w = 2 * np.pi * f
    h_d = sdof_receptance(f)
    h_v = 1j * w * h_d
    h_a = -(w**2) * h_d
    for kind, values in [("mobility", h_v), ("Accelerance", h_a), ("receptance", h_d)]:
        out = to_receptance(f, values, kind)
        if kind != "receptance":
            assert np.isnan(out[0].real) and np.isnan(out[0].imag)
        np.testing.assert_allclose(out[1:], h_d[1:], rtol=1e-12)
    # the receptance case returns a copy
    out = to_receptance(f, h_d, "receptance")
    out[1] = 0
    assert h_d[1] != 0


def test_to_receptance_errors():
    with pytest.raises(ValueError, match="unknown FRF kind"):
        to_receptance([1.0], [1.0], "inertance")
    with pytest.raises(ValueError, match="shape"):
        to_receptance([1.0, 2.0], [1.0], "mobility")


# ----------------------------------------------------------------------------- CSV


def test_csv_round_trip_exact(tmp_path: Path):
    frf = make_frf(50, response=(3, 2), reference=(1, 2))
    path = tmp_path / "a.csv"
    write_frf_csv(path, frf)
    back = read_frf_csv(path)
    np.testing.assert_array_equal(back.frequency_hz, frf.frequency_hz)
    np.testing.assert_array_equal(back.receptance, frf.receptance)
    assert back.response == (0, 0) and back.reference == (0, 0)
    assert back.source == str(path)
    assert [p.name for p in tmp_path.iterdir()] == ["a.csv"]  # no temp file left


@settings(max_examples=40, deadline=None)
@given(
    data=arrays(
        np.float64,
        st.tuples(st.integers(1, 20), st.just(2)),
        elements=st.floats(allow_nan=False, allow_infinity=False, width=64),
    ),
    start=st.floats(0.0, 1e6),
)
def test_csv_round_trip_property(tmp_path_factory, data, start):
    f = start + np.arange(data.shape[0]) * 0.1 + 1e-3 * np.arange(data.shape[0]) ** 2
    frf = FRF(f, data[:, 0] + 1j * data[:, 1])
    path = tmp_path_factory.mktemp("csv") / "p.csv"
    write_frf_csv(path, frf)
    back = read_frf_csv(path)
    np.testing.assert_array_equal(back.frequency_hz, frf.frequency_hz)
    np.testing.assert_array_equal(back.receptance, frf.receptance)


def test_csv_comments_blank_lines_bom(tmp_path: Path):
    path = tmp_path / "c.csv"
    path.write_bytes(
        "\ufeff# measured 2024\n\n  Frequency_Hz , REAL, imag  \n"
        "# a comment\n1.0, 2e-6, -1e-7  # inline\n\n2.5,3e-6,0\n".encode()
    )
    frf = read_frf_csv(path)
    np.testing.assert_array_equal(frf.frequency_hz, [1.0, 2.5])
    np.testing.assert_array_equal(frf.receptance, [2e-6 - 1e-7j, 3e-6])


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("", "no header line"),
        ("# only comments\n", "no header line"),
        ("frequency_hz,real,imag\n", "no data rows"),
        ("freq,re,im\n1,2,3\n", "line 1: expected header"),
        ("frequency_hz,real\n1,2\n", "line 1: expected header"),
        ("frequency_hz,real,imag\n1,2,3\n2,3\n", "line 3: expected 3 columns"),
        ("frequency_hz,real,imag\n1,2,3,4\n", "line 2: expected 3 columns"),
        ("# c\nfrequency_hz,real,imag\n1,2,3\n2,x1,3\n", "line 4: column real: non-numeric"),
        ("frequency_hz,real,imag\n1,2,\n", "line 2: column imag: non-numeric value ''"),
        ("frequency_hz,real,imag\n1,2,nan\n", "line 2: column imag: non-finite"),
        ("frequency_hz,real,imag\n1,2,3\n\n1,2,3\n", r"line 4: .*not greater .* \(line 2\)"),
        ("frequency_hz,real,imag\n2,2,3\n1,2,3\n", "line 3: .*strictly increasing"),
        ("frequency_hz,real,imag\n-1,2,3\n", "line 2: column frequency_hz: negative"),
    ],
)
def test_csv_bad_input(tmp_path: Path, text: str, pattern: str):
    path = tmp_path / "bad.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match=pattern) as info:
        read_frf_csv(path)
    assert str(path) in str(info.value)
    assert "\n" not in str(info.value)


def test_csv_unreadable(tmp_path: Path):
    missing = tmp_path / "missing.csv"
    with pytest.raises(InputError, match="cannot read file") as info:
        read_frf_csv(missing)
    assert str(missing) in str(info.value)
    binary = tmp_path / "bin.csv"
    binary.write_bytes(b"\xff\xfe\x00garbage\x80")
    with pytest.raises(InputError, match="not a UTF-8 text file") as info:
        read_frf_csv(binary)
    assert str(binary) in str(info.value)
    with pytest.raises(InputError, match="cannot read file"):
        read_frf_csv(tmp_path)


def test_write_csv_rejects_nan_and_keeps_old_file(tmp_path: Path):
    path = tmp_path / "out.csv"
    path.write_text("old\n")
    frf = FRF([0.0, 1.0], to_receptance([0.0, 1.0], [1.0, 1.0], "accelerance"))
    with pytest.raises(ValueError, match="not finite at 0 Hz"):
        write_frf_csv(path, frf)
    assert path.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]


def test_atomic_write_failure_leaves_target_and_no_temp(tmp_path: Path):
    path = tmp_path / "t.txt"
    path.write_text("old")

    def boom(tmp: str) -> None:
        Path(tmp).write_text("partial")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError):
        atomic_write(path, boom)
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["t.txt"]


def test_atomic_write_honours_umask(tmp_path: Path):
    old = os.umask(0o022)
    try:
        atomic_write(tmp_path / "m.txt", lambda tmp: Path(tmp).write_text("x"))
    finally:
        os.umask(old)
    assert (tmp_path / "m.txt").stat().st_mode & 0o777 == 0o644


# ----------------------------------------------------------------------------- check_same_axis


def test_check_same_axis_ok_and_tolerance():
    a = make_frf(10)
    f = a.frequency_hz * (1 + 1e-12)
    b = FRF(f, a.receptance, (2, 3), (1, 3))
    axis = check_same_axis([a, b], "set A")
    np.testing.assert_array_equal(axis, a.frequency_hz)
    assert check_same_axis([a]) is a.frequency_hz


@pytest.mark.parametrize(
    "other",
    [
        np.arange(1, 10) * 0.5,  # different length
        np.arange(1, 11) * 0.5 + 1e-6,  # shifted
    ],
)
def test_check_same_axis_mismatch(other):
    a = make_frf(10, response=(1, 3), reference=(1, 3))
    b = FRF(other, np.ones_like(other), (7, 1), (1, 3), source="b.uff")
    with pytest.raises(InputError, match="frequency axis of FRF 2") as info:
        check_same_axis([a, b], "study.toml: set 'bare'")
    msg = str(info.value)
    assert msg.startswith("study.toml: set 'bare': frequency_hz: ")
    assert "7+X/1+Z from b.uff" in msg


def test_check_same_axis_empty():
    with pytest.raises(InputError, match="no FRFs"):
        check_same_axis([], "x")
