"""Tests for eigenupdate.io.uff: datasets 58/58b (FRFs) and 55 (normal modes) via pyuff."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyuff
from _synth import viscous_sdof
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from eigenupdate.errors import InputError
from eigenupdate.io.uff import read_frfs, read_modes, write_frfs, write_modes
from eigenupdate.measure.frf import FRF, check_same_axis, to_receptance
from eigenupdate.measure.modes import Mode

# Analytic viscously damped SDOF: m x'' + c x' + k x = F.
M, K, C = 1.5, 6.0e4, 9.0


def sdof_receptance(f_hz: np.ndarray) -> np.ndarray:
    return viscous_sdof(f_hz, M, K, C)


def frf_set(f: np.ndarray) -> list[FRF]:
    h = sdof_receptance(f)
    return [
        FRF(f, h, (1, 3), (1, 3)),
        FRF(f, -0.5 * h + 1e-9j, (2, -1), (1, 3)),
        FRF(f, 0.25 * h, (3, 5), (4, -6)),
    ]


def pyuff_58(path: Path, data, x, *, binary: int = 0, spacing: int = 1, **fields) -> None:
    """Append one dataset 58 written by pyuff itself (not by eigenupdate)."""
    kw = {
        "func_type": 4,
        "rsp_node": 5,
        "rsp_dir": 3,
        "ref_node": 1,
        "ref_dir": 3,
        "abscissa_spec_data_type": 18,
        "ordinate_spec_data_type": 8,
        "orddenom_spec_data_type": 13,
    }
    kw.update(fields)
    dset = pyuff.prepare_58(
        binary=binary, data=np.asarray(data), x=np.asarray(x, float), abscissa_spacing=spacing, **kw
    )
    for key in ("ordinate_axis_units_lab", "orddenom_axis_units_lab", "abscissa_axis_units_lab"):
        if key in fields:
            dset[key] = fields[key]
    pyuff.UFF(str(path)).write_sets(dset, mode="add")


def assert_frf_equal(a: FRF, b: FRF, *, f_rtol: float = 0.0, h_rtol: float = 0.0) -> None:
    assert a.response == b.response and a.reference == b.reference
    np.testing.assert_allclose(a.frequency_hz, b.frequency_hz, rtol=f_rtol, atol=0)
    scale = np.max(np.abs(b.receptance))
    np.testing.assert_allclose(a.receptance, b.receptance, rtol=h_rtol, atol=h_rtol * scale)


# ----------------------------------------------------------------------------- 58 round trip


def test_ascii_58_round_trip(tmp_path: Path):
    f = np.arange(1, 801) * 0.125  # min and increment exact in 6 digits
    frfs = frf_set(f)
    path = tmp_path / "a.uff"
    write_frfs(path, frfs)
    back = read_frfs(path)
    assert len(back) == 3
    for a, b in zip(back, frfs, strict=True):
        assert a.source == str(path)
        np.testing.assert_array_equal(a.frequency_hz, b.frequency_hz)
        # ASCII double precision: pyuff writes %20.11e (12 significant digits)
        assert_frf_equal(a, b, h_rtol=6e-12)
    raw = pyuff.UFF(str(path)).read_sets(0)
    assert raw["func_type"] == 4 and raw["ord_data_type"] == 6 and raw["binary"] == 0
    assert raw["abscissa_spacing"] == 1
    assert raw["ordinate_spec_data_type"] == 8 and raw["orddenom_spec_data_type"] == 13
    assert raw["abscissa_spec_data_type"] == 18
    assert [p.name for p in tmp_path.iterdir()] == ["a.uff"]


@pytest.mark.parametrize(
    "f",
    [
        np.arange(0, 513) * 0.125,  # exactly representable uniform axis (even spacing)
        np.arange(1, 1001) * (10000 / 32768),  # uniform, increment not 6-digit exact
        np.geomspace(1.0, 3000.0, 300),  # non-uniform
    ],
    ids=["uniform", "uniform-inexact", "non-uniform"],
)
def test_binary_58b_round_trip_exact(tmp_path: Path, f: np.ndarray):
    frfs = frf_set(f)
    path = tmp_path / "b.uff"
    write_frfs(path, frfs, binary=True)
    assert b"    58b" in path.read_bytes()[:20]
    back = read_frfs(path)
    for a, b in zip(back, frfs, strict=True):
        np.testing.assert_array_equal(a.frequency_hz, b.frequency_hz)
        np.testing.assert_array_equal(a.receptance, b.receptance)
        assert a.response == b.response and a.reference == b.reference


@settings(max_examples=25, deadline=None)
@given(
    re_im=arrays(
        np.float64,
        st.tuples(st.integers(2, 40), st.just(2)),
        elements=st.floats(-1e3, 1e3, allow_nan=False, allow_subnormal=False),
    ),
    df=st.sampled_from([0.1, 0.25, 1 / 3, 2.0]),
)
def test_binary_58b_round_trip_property(tmp_path_factory, re_im, df):
    f = np.arange(re_im.shape[0]) * df
    frf = FRF(f, re_im[:, 0] + 1j * re_im[:, 1], (9, 2), (1, 1))
    path = tmp_path_factory.mktemp("b") / "p.uff"
    write_frfs(path, [frf], binary=True)
    (back,) = read_frfs(path)
    np.testing.assert_array_equal(back.receptance, frf.receptance)
    np.testing.assert_allclose(back.frequency_hz, f, rtol=1e-9, atol=1e-9 * f[-1])


@pytest.mark.parametrize(
    "f",
    [np.arange(1, 1001) * (10000 / 32768), np.geomspace(1.0, 3000.0, 300)],
    ids=["uniform-inexact", "non-uniform"],
)
def test_ascii_58_abscissa_has_6_digits(tmp_path: Path, f: np.ndarray):
    frfs = frf_set(f)
    path = tmp_path / "a.uff"
    write_frfs(path, frfs)
    for a, b in zip(read_frfs(path), frfs, strict=True):
        assert_frf_equal(a, b, f_rtol=5e-6, h_rtol=6e-12)


def test_write_ascii_rejects_lines_closer_than_6_digits(tmp_path: Path):
    f = 10000.0 + np.array([0.0, 0.01, 0.05])
    frf = FRF(f, np.ones(3), (1, 1), (1, 1))
    with pytest.raises(ValueError, match="binary=True"):
        write_frfs(tmp_path / "x.uff", [frf])
    write_frfs(tmp_path / "x.uff", [frf], binary=True)
    np.testing.assert_array_equal(read_frfs(tmp_path / "x.uff")[0].frequency_hz, f)


def test_write_frfs_refuses_nan_and_keeps_old_file(tmp_path: Path):
    path = tmp_path / "out.uff"
    path.write_text("old")
    f = np.arange(0, 10) * 1.0
    acc = to_receptance(f, np.ones(10), "accelerance")  # NaN at 0 Hz
    with pytest.raises(ValueError, match="not finite at 0 Hz"):
        write_frfs(path, [FRF(f, acc, (1, 1), (1, 1))])
    with pytest.raises(ValueError, match="no FRFs"):
        write_frfs(path, [])
    with pytest.raises(ValueError, match="fewer than 2"):
        write_frfs(path, [FRF([1.0], [1.0])])
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.uff"]


def test_write_frfs_replaces_existing_file(tmp_path: Path):
    path = tmp_path / "r.uff"
    f = np.arange(1, 11) * 1.0
    write_frfs(path, frf_set(f))
    write_frfs(path, frf_set(f)[:1], binary=True)
    assert len(read_frfs(path)) == 1


def test_mixed_ascii_and_binary_file(tmp_path: Path):
    path = tmp_path / "mix.uff"
    f = np.arange(1, 21) * 0.5
    h = sdof_receptance(f)
    pyuff_58(path, h, f, binary=0, rsp_node=1)
    pyuff_58(path, 2 * h, f, binary=1, rsp_node=2)
    back = read_frfs(path)
    assert [b.response for b in back] == [(1, 3), (2, 3)]
    np.testing.assert_allclose(back[1].receptance, 2 * h, rtol=0)
    axis = check_same_axis(back, path)
    np.testing.assert_array_equal(axis, f)


# ----------------------------------------------------------------------------- conversion


@pytest.mark.parametrize("binary", [0, 1])
def test_read_pyuff_velocity_and_acceleration(tmp_path: Path, binary: int):
    f = np.linspace(0.0, 80.0, 321)
    w = 2 * np.pi * f
    h = sdof_receptance(f)
    path = tmp_path / "va.uff"
    pyuff_58(path, 1j * w * h, f, binary=binary, ordinate_spec_data_type=11)
    pyuff_58(path, -(w**2) * h, f, binary=binary, ordinate_spec_data_type=12)
    pyuff_58(path, h, f, binary=binary, ordinate_spec_data_type=8)
    mob, acc, rec = read_frfs(path)
    for frf in (mob, acc):
        assert np.isnan(frf.receptance[0])  # 0 Hz: undefined
        np.testing.assert_allclose(frf.receptance[1:], h[1:], rtol=1e-10)
    np.testing.assert_allclose(rec.receptance, h, rtol=1e-10)


@pytest.mark.parametrize(
    ("spec", "num", "den", "factor"),
    [
        (12, "g", "N", 9.80665),
        (12, "m/s^2", "NONE", 1.0),
        (12, "(m/s²)", "N", 1.0),
        (11, "mm/s", "N", 1e-3),
        (8, "mm", "kN", 1e-6),
        (12, "g/N", "NONE", 9.80665),
        (12, "g/lbf", "lbf", 9.80665 / 4.4482216152605),
        (11, "in/s", "lbf", 0.0254 / 4.4482216152605),
        (0, "m/s^2", "N", 1.0),  # unknown type: kind from the label
        (1, "g", "NONE", 9.80665),
    ],
)
def test_units_labels_are_converted(tmp_path: Path, spec, num, den, factor):
    f = np.arange(1, 41) * 1.0
    w = 2 * np.pi * f
    h = sdof_receptance(f)
    kind = {8: 0, 11: 1, 12: 2}.get(spec, 2)
    values = [h, 1j * w * h, -(w**2) * h][kind] / factor
    path = tmp_path / "u.uff"
    pyuff_58(
        path,
        values,
        f,
        ordinate_spec_data_type=spec,
        ordinate_axis_units_lab=num,
        orddenom_axis_units_lab=den,
    )
    (frf,) = read_frfs(path)
    np.testing.assert_allclose(frf.receptance, h, rtol=1e-10)


def test_abscissa_in_rad_per_s(tmp_path: Path):
    f = np.arange(1, 11) * 1.0
    path = tmp_path / "rad.uff"
    pyuff_58(path, sdof_receptance(f), 2 * np.pi * f, abscissa_axis_units_lab="rad/s", spacing=0)
    (frf,) = read_frfs(path)
    np.testing.assert_allclose(frf.frequency_hz, f, rtol=1e-5)


def test_unknown_ordinate_type_needs_default_kind(tmp_path: Path):
    f = np.arange(1, 11) * 1.0
    w = 2 * np.pi * f
    h = sdof_receptance(f)
    path = tmp_path / "unk.uff"
    pyuff_58(path, -(w**2) * h, f, ordinate_spec_data_type=0)
    with pytest.raises(InputError, match="says whether the FRF is") as info:
        read_frfs(path)
    assert info.value.field == "ordinate_spec_data_type" and str(path) in str(info.value)
    (frf,) = read_frfs(path, default_kind="accelerance")
    np.testing.assert_allclose(frf.receptance, h, rtol=1e-10)
    with pytest.raises(ValueError, match="default_kind"):
        read_frfs(path, default_kind="inertance")


def test_rotational_dofs_round_trip(tmp_path: Path):
    f = np.arange(1, 11) * 1.0
    frf = FRF(f, sdof_receptance(f), (4, -5), (2, 6))
    path = tmp_path / "rot.uff"
    write_frfs(path, [frf])
    raw = pyuff.UFF(str(path)).read_sets(0)
    assert raw["ordinate_axis_units_lab"] == "rad" and raw["orddenom_axis_units_lab"] == "N*m"
    (back,) = read_frfs(path)
    assert back.response == (4, -5) and back.reference == (2, 6)


# ----------------------------------------------------------------------------- function types


def test_non_frf_58_datasets_are_skipped(tmp_path: Path):
    t = np.arange(0, 64) * 1e-3
    f = np.arange(1, 11) * 1.0
    path = tmp_path / "mixed.uff"
    pyuff_58(path, np.sin(t), t, func_type=1, abscissa_spec_data_type=17)  # time response
    pyuff_58(path, sdof_receptance(f), f)
    pyuff_58(path, np.ones(10) + 0j, f, func_type=6)  # coherence
    (frf,) = read_frfs(path)
    assert frf.response == (5, 3)


def test_only_time_responses_rejected(tmp_path: Path):
    t = np.arange(0, 64) * 1e-3
    path = tmp_path / "time.uff"
    pyuff_58(path, np.sin(t), t, func_type=1, abscissa_spec_data_type=17)
    with pytest.raises(InputError, match=r"no FRF dataset \(type 58\) in file.*1 \(time") as info:
        read_frfs(path)
    assert info.value.field == "func_type"
    assert str(info.value).startswith(f"{path}: func_type: ")


# ----------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("data", "x", "fields", "field", "pattern"),
    [
        (np.ones(10), np.arange(1.0, 11), {}, "ord_data_type", "real double precision"),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {"orddenom_spec_data_type": 12},
            "orddenom_spec_data_type",
            "not a force",
        ),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {"ordinate_spec_data_type": 2},
            "ordinate_spec_data_type",
            r"response type 2 \(stress\)",
        ),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {"abscissa_spec_data_type": 17},
            "abscissa_spec_data_type",
            r"abscissa type 17 \(time\)",
        ),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {"ordinate_spec_data_type": 12, "ordinate_axis_units_lab": "mm"},
            "ordinate_axis_units_lab",
            "units 'mm' not recognised as acceleration units",
        ),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {"orddenom_axis_units_lab": "furlong"},
            "orddenom_axis_units_lab",
            "force units 'furlong' not recognised",
        ),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {"abscissa_axis_units_lab": "s"},
            "abscissa_axis_units_lab",
            "abscissa units 's' not recognised",
        ),
        (
            np.ones(10) + 1j,
            np.arange(1.0, 11),
            {
                "ordinate_axis_units_lab": "g/N",
                "ordinate_spec_data_type": 12,
                "orddenom_axis_units_lab": "lbf",
            },
            "orddenom_axis_units_lab",
            "contradict",
        ),
    ],
)
def test_bad_58_fields(tmp_path: Path, data, x, fields, field, pattern):
    path = tmp_path / "bad.uff"
    pyuff_58(path, data, x, **fields)
    with pytest.raises(InputError, match=pattern) as info:
        read_frfs(path)
    msg = str(info.value)
    assert info.value.field == field
    assert msg.startswith(f"{path}: {field}: dataset 1 (5+Z/1+Z): ")
    assert "\n" not in msg


def test_non_increasing_uneven_abscissa(tmp_path: Path):
    path = tmp_path / "dec.uff"
    pyuff_58(path, np.ones(5) + 1j, [1.0, 2.0, 3.0, 3.0, 4.0], spacing=0)
    with pytest.raises(InputError, match="not strictly increasing: 3 Hz at point 4") as info:
        read_frfs(path)
    assert info.value.field == "abscissa" and str(path) in str(info.value)


def test_negative_even_increment(tmp_path: Path):
    path = tmp_path / "neg.uff"
    pyuff_58(path, np.ones(5) + 1j, [5.0, 4.0, 3.0, 2.0, 1.0], spacing=1)
    with pytest.raises(InputError, match="abscissa increment -1 must be > 0") as info:
        read_frfs(path)
    assert info.value.field == "abscissa_inc"


def test_negative_frequency(tmp_path: Path):
    path = tmp_path / "negf.uff"
    pyuff_58(path, np.ones(5) + 1j, np.arange(-2.0, 3.0), spacing=1)
    with pytest.raises(InputError, match="negative frequency -2 Hz"):
        read_frfs(path)


def test_non_uniform_abscissa_only_rejected_on_request(tmp_path: Path):
    path = tmp_path / "nonuni.uff"
    f = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    pyuff_58(path, np.ones(5) + 1j, f, spacing=0)
    np.testing.assert_array_equal(read_frfs(path)[0].frequency_hz, f)
    with pytest.raises(InputError, match="not uniformly spaced") as info:
        read_frfs(path, require_uniform=True)
    assert info.value.field == "abscissa_spacing"
    # a uniform axis stored unevenly with 6 digits still counts as uniform
    path2 = tmp_path / "uni.uff"
    pyuff_58(path2, np.ones(200) + 1j, 1234.5678 + 0.37 * np.arange(200), spacing=0)
    assert len(read_frfs(path2, require_uniform=True)) == 1


def test_missing_data_line_is_reported(tmp_path: Path):
    path = tmp_path / "short.uff"
    pyuff_58(path, np.arange(10) + 1j, np.arange(1.0, 11))
    lines = path.read_text().splitlines(keepends=True)
    del lines[14]  # a data line (2 complex values) of 5
    path.write_text("".join(lines))
    with pytest.raises(InputError, match="announces 10 values but 8 were read") as info:
        read_frfs(path)
    assert info.value.field == "num_pts"


def test_truncated_file(tmp_path: Path):
    path = tmp_path / "trunc.uff"
    f = np.arange(1, 101) * 1.0
    write_frfs(path, frf_set(f))
    raw = path.read_bytes()
    path.write_bytes(raw[: len(raw) - 500])
    with pytest.raises(InputError, match="truncated") as info:
        read_frfs(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize(
    ("content", "pattern"),
    [
        (b"", "no FRF dataset \\(type 58\\) in file; no universal-file datasets found"),
        (bytes(range(256)) * 20, "no FRF dataset \\(type 58\\) in file"),
        (b"frequency_hz,real,imag\n1,2,3\n", "no FRF dataset \\(type 58\\) in file"),
        (b"    -1\n    58\ngarbage\n    -1\n", "dataset 1 \\(type 58\\): pyuff cannot parse it"),
        (
            b"    -1\n  abc\nfoo\n    -1\n",
            "line 2: no dataset type after the '-1' delimiter that opens dataset 1",
        ),
    ],
    ids=["empty", "binary-junk", "csv", "broken-58", "broken-header"],
)
def test_garbage_files(tmp_path: Path, content: bytes, pattern: str):
    path = tmp_path / "junk.uff"
    path.write_bytes(content)
    with pytest.raises(InputError, match=pattern) as info:
        read_frfs(path)
    assert str(info.value).startswith(f"{path}: ")
    assert "\n" not in str(info.value)


def test_unreadable_paths(tmp_path: Path):
    missing = tmp_path / "nope.uff"
    with pytest.raises(InputError, match="cannot read file") as info:
        read_frfs(missing)
    assert str(missing) in str(info.value)
    with pytest.raises(InputError, match="is a directory"):
        read_frfs(tmp_path)
    with pytest.raises(InputError, match="cannot read file"):
        read_modes(missing)


def test_frfs_from_two_files_with_different_axes(tmp_path: Path):
    a, b = tmp_path / "a.uff", tmp_path / "b.uff"
    write_frfs(a, frf_set(np.arange(1, 101) * 0.5))
    write_frfs(b, frf_set(np.arange(1, 101) * 0.25))
    frfs = read_frfs(a) + read_frfs(b)
    with pytest.raises(InputError, match="frequency axis of FRF 4") as info:
        check_same_axis(frfs, "set 'bare'")
    assert str(b) in str(info.value) and str(a) in str(info.value)


# ----------------------------------------------------------------------------- 55 modes


def test_modes_55_round_trip(tmp_path: Path):
    rng = np.random.default_rng(0)
    modes = [
        Mode(
            12.5,
            loss_factor=0.0125,
            damping_ratio=0.004,
            modal_mass=1.75,
            node_nums=[1, 2, 3, 10],
            shape=rng.standard_normal((4, 3)),
        ),
        Mode(
            47.123456789,
            loss_factor=0.0031415926,
            node_nums=[1, 2],
            shape=rng.standard_normal((2, 6)),
            mode_number=7,
        ),
        Mode.point(88.0, 2.5e-3, (5, -2), loss_factor=0.02),
    ]
    path = tmp_path / "modes.uff"
    write_modes(path, modes)
    back = read_modes(path)
    assert [m.mode_number for m in back] == [1, 7, 3]
    for a, b in zip(back, modes, strict=True):
        assert a.source == str(path)
        # dataset 55 stores 6 significant digits (%13.5e)
        for name in ("frequency_hz", "loss_factor", "damping_ratio", "modal_mass"):
            assert getattr(a, name) == pytest.approx(getattr(b, name), rel=5e-6, abs=0)
        np.testing.assert_array_equal(a.node_nums, b.node_nums)
        np.testing.assert_allclose(a.shape, b.shape, rtol=5e-6, atol=0)
    np.testing.assert_array_equal(back[2].shape, [[0.0, -2.5e-3, 0.0]])
    # the loss factor really is pyuff's hysteretic damping field of analysis type 2
    raw = pyuff.UFF(str(path)).read_sets(0)
    assert raw["analysis_type"] == 2
    assert raw["modal_damp_his"] == pytest.approx(0.0125, rel=1e-6)
    assert raw["modal_damp_vis"] == pytest.approx(0.004, rel=1e-6)
    assert raw["modal_m"] == pytest.approx(1.75, rel=1e-6)
    assert raw["freq"] == pytest.approx(12.5, rel=1e-6)


def test_read_modes_written_by_pyuff_and_skips_others(tmp_path: Path):
    path = tmp_path / "pm.uff"
    f = np.arange(1, 11) * 1.0
    pyuff_58(path, sdof_receptance(f), f)
    dset = pyuff.prepare_55(
        model_type=1,
        analysis_type=2,
        data_ch=2,
        spec_data_type=8,
        data_type=2,
        n_data_per_node=3,
        node_nums=[4, 5],
        load_case=1,
        mode_n=3,
        freq=33.0,
        modal_m=0.0,
        modal_damp_vis=0.01,
        modal_damp_his=0.05,
        r1=np.array([1.0, 2.0]),
        r2=np.array([0.0, 0.0]),
        r3=np.array([-1.0, 0.5]),
    )
    pyuff.UFF(str(path)).write_sets(dset, mode="add")
    (mode,) = read_modes(path)
    assert (mode.frequency_hz, mode.loss_factor, mode.damping_ratio) == (33.0, 0.05, 0.01)
    assert mode.mode_number == 3
    np.testing.assert_array_equal(mode.shape, [[1.0, 0.0, -1.0], [2.0, 0.0, 0.5]])
    assert len(read_frfs(path)) == 1  # the 55 set is skipped by read_frfs


def test_read_modes_without_modes(tmp_path: Path):
    path = tmp_path / "frf.uff"
    write_frfs(path, frf_set(np.arange(1, 11) * 1.0))
    with pytest.raises(InputError, match="no normal-mode dataset.*found dataset types \\[58\\]"):
        read_modes(path)


def test_read_modes_broken_dataset(tmp_path: Path):
    path = tmp_path / "m.uff"
    write_modes(path, [Mode(10.0)])
    path.write_text(path.read_text().replace("1.00000e+01", "     garbage"))
    with pytest.raises(InputError, match="dataset 1 \\(type 55\\): pyuff cannot parse") as info:
        read_modes(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"frequency_hz": -1.0}, "frequency_hz"),
        ({"frequency_hz": float("nan")}, "frequency_hz"),
        ({"frequency_hz": 1.0, "loss_factor": "x"}, "loss_factor"),
        ({"frequency_hz": 1.0, "node_nums": []}, "node_nums"),
        ({"frequency_hz": 1.0, "node_nums": [1.5]}, "node_nums"),
        ({"frequency_hz": 1.0, "node_nums": [1, 2], "shape": np.zeros((2, 4))}, "shape"),
        ({"frequency_hz": 1.0, "shape": [[1j, 0, 0]]}, "shape"),
        ({"frequency_hz": 1.0, "mode_number": 1.5}, "mode_number"),
    ],
)
def test_mode_validation(kwargs, field):
    with pytest.raises(InputError) as info:
        Mode(**kwargs)
    assert info.value.field == field


def test_write_modes_empty(tmp_path: Path):
    with pytest.raises(ValueError, match="no modes"):
        write_modes(tmp_path / "m.uff", [])
    with pytest.raises(ValueError, match="direction"):
        Mode.point(1.0, 1.0, (1, 0))


def test_read_ascii_single_precision(tmp_path: Path):
    f = np.arange(1, 51) * 0.5
    h = sdof_receptance(f)
    path = tmp_path / "single.uff"
    dset = pyuff.prepare_58(
        func_type=4, rsp_node=1, rsp_dir=1, ref_node=1, ref_dir=1, data=h, x=f,
        ord_data_type=5, abscissa_spacing=1, abscissa_spec_data_type=18,
        ordinate_spec_data_type=8, orddenom_spec_data_type=13,
    )  # fmt: skip
    pyuff.UFF(str(path)).write_sets(dset, mode="add", force_double=False)
    (frf,) = read_frfs(path)
    np.testing.assert_allclose(frf.receptance, h, rtol=1e-5)  # E13.5: 6 digits


def test_binary_block_with_missing_bytes(tmp_path: Path):
    path = tmp_path / "cut.uff"
    write_frfs(path, frf_set(np.arange(1, 11) * 1.0)[:1], binary=True)
    raw = path.read_bytes()
    end = raw.rindex(b"    -1")
    path.write_bytes(raw[: end - 16] + raw[end:])  # drop one complex value
    with pytest.raises(InputError, match="announces 10 values but 9 were read") as info:
        read_frfs(path)
    assert str(path) in str(info.value)


# ----------------------------------------------------------------------------- issue 9 labels


@pytest.mark.parametrize(
    ("spec", "label", "kind"),
    [
        (1, "(1/N)*(m/s^2)", 2),
        (1, "(1/N)*(m/s²)", 2),
        (12, "(1/N)*(m/s²)", 2),
        (1, "(m/s²)/N", 2),
        (1, "m/s^2/N", 2),
        (1, "(m/s^2)*(1/N)", 2),
        (1, "(m/s)/N", 1),
        (1, "m/N", 0),
        (0, "g/N", 2),
    ],
)
def test_units_labels_as_engineers_write_them(tmp_path: Path, spec, label, kind):
    # function type 4, ordinate type 1 (general): the label says what the FRF is
    f = np.arange(1, 41) * 1.0
    w = 2 * np.pi * f
    h = sdof_receptance(f)
    factor = 9.80665 if label.startswith("g") else 1.0
    values = [h, 1j * w * h, -(w**2) * h][kind] / factor
    path = tmp_path / "u.uff"
    pyuff_58(path, values, f, ordinate_spec_data_type=spec, ordinate_axis_units_lab=label,
             orddenom_axis_units_lab="NONE")
    (frf,) = read_frfs(path)
    np.testing.assert_allclose(frf.receptance, h, rtol=1e-10)


def test_latin1_superscript_two_reads_as_squared(tmp_path: Path):
    """A label written by a non-UTF-8 program: the byte 0xB2 ('²' in Latin-1)."""
    f = np.arange(1, 41) * 1.0
    w = 2 * np.pi * f
    h = sdof_receptance(f)
    path = tmp_path / "l1.uff"
    pyuff_58(path, -(w**2) * h, f, ordinate_spec_data_type=1,
             ordinate_axis_units_lab="(1/N)*(m/s^2)", orddenom_axis_units_lab="NONE")
    raw = path.read_bytes()
    assert b"(1/N)*(m/s^2)" in raw
    path.write_bytes(raw.replace(b"(1/N)*(m/s^2)", b"(1/N)*(m/s\xb2) "))
    (frf,) = read_frfs(path)
    np.testing.assert_allclose(frf.receptance, h, rtol=1e-10)


def test_unknown_label_names_the_label_and_the_option(tmp_path: Path):
    f = np.arange(1, 11) * 1.0
    path = tmp_path / "x.uff"
    pyuff_58(path, sdof_receptance(f), f, ordinate_spec_data_type=1,
             ordinate_axis_units_lab="EU/EU")
    with pytest.raises(InputError) as info:
        read_frfs(path)
    msg = str(info.value)
    assert "'EU/EU'" in msg and '[measurement.frf_options] kind = "accelerance"' in msg
    assert "\n" not in msg


@pytest.mark.parametrize("binary", [False, True])
@pytest.mark.parametrize("blank", [b"\n", b"   \n", b"\r\n"])
def test_blank_line_after_an_opening_delimiter(tmp_path: Path, binary: bool, blank: bytes):
    """Issue 23: pyuff reads the blank line as the type of the dataset and skips it, so
    the file read as 2 FRFs of 3 and the next resonance was taken for the missing mode's.
    Now an error naming the line and the dataset; a blank line between datasets (after a
    closing delimiter) is still harmless."""
    path = tmp_path / "f.uff"
    write_frfs(path, frf_set(np.linspace(1.0, 100.0, 50)), binary=binary)
    raw = path.read_bytes()
    u = pyuff.UFF(str(path))
    u.get_set_types()
    blocks = u._block_ind  # pyuff's own pairing of the tags: [opening, closing - 1]
    assert len(blocks) == 3
    cut = int(blocks[1][0]) + len(b"    -1\n")  # opening tag of dataset 2
    path.write_bytes(raw[:cut] + blank + raw[cut:])
    with pytest.raises(InputError, match="dataset 2: line [0-9]+: a blank line after the "
                                         "'-1' delimiter that opens dataset 2"):
        read_frfs(path)
    closing = int(blocks[0][1]) + 1 + len(b"    -1\n")  # closing tag of dataset 1
    path.write_bytes(raw[:closing] + blank + raw[closing:])
    assert len(read_frfs(path)) == 3
