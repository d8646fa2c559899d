"""Assembly time of a ~500k-coordinate flat-plate shell mesh (issue 20: target 10 s).

Times, in the same run:

* baseline: ``frame.build_frame`` of a space frame of about the same number of
  coordinates (the frame-element assembly, vectorised, with its 30 parameter matrices);
* CQUAD4: element stiffness parts and mass of a square plate of 290 x 290 MITC4 elements
  (508,086 coordinates), combined for one thickness (K = T (K_m + K_drill + K_s) +
  T^3 K_b, M = rho T M) and summed into CSR 6 x 6 node block by node block, in chunks
  of 8192 elements;
* CTRIA3: the same grid cut into 2 x 290 x 290 triangles;
* with ``--deck`` (nastran environment): the CQUAD4 plate written as a BDF (GRID,
  CQUAD4, PSHELL, MAT1; MAT1 E and RHO as parameters) and read through
  :func:`eigenupdate.io.nastran.read_nastran`, against pyNastran's ``read_bdf`` alone
  (parsing) in the same run; the difference is eigenupdate's validation and assembly.

Run: ``.venv/bin/python benchmarks/bench_shells.py`` (``--size small`` for a quick run;
``.venv-nastran/bin/python benchmarks/bench_shells.py --deck`` adds the deck path).
Prints each time, the ratio to the baseline, and a check that the plate's matrices are
symmetric with the six rigid-body motions of a free plate stress-free.
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from frame import build_frame  # noqa: E402

from eigenupdate.model import shells  # noqa: E402
from eigenupdate.model.assembly import assemble  # noqa: E402

SIZES = {"full": (290, 37), "small": (60, 4)}  # plate cells per side, frame n_sub


def plate(nx: int, triangles: bool):
    x, y = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, nx + 1), indexing="ij")
    xyz = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    nid = np.arange(x.size).reshape(nx + 1, nx + 1)
    quads = np.column_stack([nid[:-1, :-1].ravel(), nid[1:, :-1].ravel(),
                             nid[1:, 1:].ravel(), nid[:-1, 1:].ravel()])
    if triangles:
        return xyz, np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return xyz, quads


def assemble_plate(xyz, el, T=0.005, E=70e9, nu=0.33, rho=2700.0):
    moduli = shells.pshell_moduli(E, nu)
    N = xyz.shape[0]
    K = assemble(el, lambda s: shells.pshell_stiffness(xyz[el[s]], T, *moduli), N, 6)
    # the mass couples translations only: sum 3 x 3 node blocks, then place them
    tr = (6 * np.arange(el.shape[1])[:, None] + np.arange(3)).ravel()
    M3 = assemble(el, lambda s: rho * T * shells.shell_mass(xyz[el[s]], False)[:, tr[:, None], tr],
                  N, 3).tocoo()
    M = sp.coo_array((M3.data, (6 * (M3.row // 3) + M3.row % 3, 6 * (M3.col // 3) + M3.col % 3)),
                     shape=(6 * N, 6 * N)).tocsr()
    return K, M


def check(xyz, K, M) -> str:
    """Symmetry and the free plate's rigid-body motions (u = t + theta x x)."""
    asym = abs(K - K.T).max() / abs(K).max()
    worst = 0.0
    for t, th in [(e, np.zeros(3)) for e in np.eye(3)] + [(np.zeros(3), e) for e in np.eye(3)]:
        u = np.column_stack([t + np.cross(th, xyz), np.broadcast_to(th, xyz.shape)]).ravel()
        worst = max(worst, np.linalg.norm(K @ u) / (abs(K).max() * np.linalg.norm(u)))
    return f"asymmetry {asym:.1e}, rigid-motion residual {worst:.1e} (relative)"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", choices=sorted(SIZES), default="full")
    ap.add_argument("--deck", action="store_true", help="also time the BDF path")
    args = ap.parse_args()
    nx, n_sub = SIZES[args.size]
    t0, c0 = time.perf_counter(), time.process_time()
    frame = build_frame(7, 5, 18, n_sub, supports="free")
    base, cbase = time.perf_counter() - t0, time.process_time() - c0
    n_frame = frame.model.n if hasattr(frame, "model") else None
    print(f"baseline  frame assembly ({n_frame} coordinates, 30 parameter matrices): "
          f"{base:.2f} s (CPU {cbase:.2f} s)")
    for triangles in (False, True):
        xyz, el = plate(nx, triangles)
        t0, c0 = time.perf_counter(), time.process_time()
        K, M = assemble_plate(xyz, el)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
        name = "CTRIA3" if triangles else "CQUAD4"
        print(f"{name}    {el.shape[0]} elements, {K.shape[0]} coordinates, nnz(K) {K.nnz}: "
              f"{dt:.2f} s (CPU {cpu:.2f} s)  ({dt / base:.2f} x baseline, CPU "
              f"{cpu / cbase:.2f} x)")
        print(f"          {check(xyz, K, M)}")
    if args.deck:
        deck(nx)


def deck(nx: int) -> None:
    """Time the BDF path on the CQUAD4 plate: pyNastran's parse alone, then read_nastran
    (parse + validation + assembly of K0, M0 and the two parameters' K_j, M_j)."""
    import tempfile
    import warnings
    from pathlib import Path

    from pyNastran.bdf.bdf import read_bdf

    from eigenupdate.io.nastran import CardField, read_nastran
    from eigenupdate.model.parameters import Parameter

    xyz, el = plate(nx, False)
    lines = ["PARAM,COUPMASS,1", "PSHELL,1,1,.005,1,,1", "MAT1,1,7.e10,,.33,2700."]
    lines += [f"GRID,{i + 1},,{x:.6f},{y:.6f},0." for i, (x, y, _) in enumerate(xyz)]
    lines += [f"CQUAD4,{k + 1},1,{a + 1},{b + 1},{c + 1},{d + 1}" for k, (a, b, c, d)
              in enumerate(el)]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "plate.bdf"
        path.write_text("\n".join(lines + ["ENDDATA", ""]))
        t0, c0 = time.perf_counter(), time.process_time()
        read_bdf(str(path), punch=True, xref=False, debug=None)
        base, cbase = time.perf_counter() - t0, time.process_time() - c0
        specs = [(Parameter("E", 0.0), CardField("MAT1", 1, "E")),
                 (Parameter("rho", 0.0), CardField("MAT1", 1, "RHO"))]
        t0, c0 = time.perf_counter(), time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            nm = read_nastran(path, specs)
        dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    coordinate_table(nm.model.coordinates)
    print(f"deck      pyNastran read_bdf alone ({xyz.shape[0]} GRID, {el.shape[0]} CQUAD4): "
          f"{base:.2f} s (CPU {cbase:.2f} s)")
    print(f"deck      read_nastran ({nm.model.n} free coordinates, 2 parameters): {dt:.2f} s "
          f"(CPU {cpu:.2f} s)  ({dt / base:.2f} x read_bdf; assembly and checks "
          f"{dt - base:.2f} s, CPU {cpu - cbase:.2f} s)")


def coordinate_table(numbers: np.ndarray) -> None:
    """The deck's coordinate table (coordinate 10 GRID + component) made as
    io/nastran.py makes it, one Coordinate record per coordinate, against
    CoordinateTable.from_arrays (three arrays, records on demand), in the same run."""
    from eigenupdate.model.coordinates import Coordinate, CoordinateTable

    c = np.asarray(numbers)
    t0 = time.perf_counter()
    records = CoordinateTable(tuple(Coordinate(int(v), int(v) // 10, int(v) % 10) for v in c))
    missing = [v for v in c.tolist() if v not in records]  # ParametricModel's check
    base = time.perf_counter() - t0
    t0 = time.perf_counter()
    table = CoordinateTable.from_arrays(c, c // 10, c % 10)
    missing += [v for v in c.tolist() if v not in table]
    dt = time.perf_counter() - t0
    assert table == records and not missing
    print(f"deck      coordinate table of {c.size} coordinates: records {base:.2f} s, "
          f"from_arrays {dt:.2f} s ({base / dt:.1f} x faster; both with the model's "
          f"membership check)")


if __name__ == "__main__":
    main()
