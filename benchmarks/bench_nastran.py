"""Load + assembly time of a NASTRAN frame BDF of about 100k coordinates.

Writes a 3-D steel space frame (CBAR/PBAR/MAT1, CONM2 floor masses, clamped bases by
SPC1) to a temporary BDF, then times, in the same run:

* baseline: pyNastran's ``BDF.read_bdf`` alone (parsing the cards);
* eigenupdate's :func:`eigenupdate.io.nastran.read_nastran`: the same parse, validation
  and assembly of K0, M0 and the parameters' K_j, M_j (here E and RHO of the columns'
  and the beams' materials).

Run in the nastran environment: ``.venv-nastran/bin/python benchmarks/bench_nastran.py``
(``--size small`` for a quick run). Prints the times and their ratio.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

SIZES = {"full": (7, 5, 18, 8), "small": (3, 2, 4, 4)}  # bays x, bays y, storeys, per member


def write_frame(path: Path, nbx: int, nby: int, ns: int, n_sub: int) -> int:
    """Write the frame; returns the number of grids."""
    x = np.arange(nbx + 1) * 6.0
    y = np.arange(nby + 1) * 5.5
    z = np.arange(ns + 1) * 3.5
    lines = ["SOL 103", "CEND", "SUBCASE 1", "  SPC = 1", "BEGIN BULK", "PARAM,COUPMASS,1"]
    joint = {}
    nid = 0
    for i, xi in enumerate(x):
        for j, yj in enumerate(y):
            for k, zk in enumerate(z):
                nid += 1
                joint[i, j, k] = nid
                lines.append(f"GRID,{nid},,{xi:.4f},{yj:.4f},{zk:.4f}")
    eid = 0
    members = []
    for (i, j, k), a in joint.items():
        if k < ns:
            members.append((a, joint[i, j, k + 1], 1, "1.,0.,0."))
        if k > 0 and i < nbx:
            members.append((a, joint[i + 1, j, k], 2, "0.,0.,1."))
        if k > 0 and j < nby:
            members.append((a, joint[i, j + 1, k], 2, "0.,0.,1."))
    pos = {n: np.array([x[i], y[j], z[k]]) for (i, j, k), n in joint.items()}
    for a, b, pid, v in members:
        chain = [a]
        for t in range(1, n_sub):
            nid += 1
            p = pos[a] + (pos[b] - pos[a]) * t / n_sub
            lines.append(f"GRID,{nid},,{p[0]:.4f},{p[1]:.4f},{p[2]:.4f}")
            chain.append(nid)
        chain.append(b)
        for p, q in zip(chain[:-1], chain[1:], strict=True):
            eid += 1
            lines.append(f"CBAR,{eid},{pid},{p},{q},{v}")
    lines += ["PBAR,1,1,1.491-2,8.563-5,2.517-4,1.850-6",
              "PBAR,2,2,8.446-3,1.318-5,2.313-4,5.110-7",
              "MAT1,1,2.1+11,,0.3,7850.", "MAT1,2,2.1+11,,0.3,7850."]
    for (_, _, k), n in joint.items():
        if k == 0:
            lines.append(f"SPC1,1,123456,{n}")
        else:
            lines.append(f"CONM2,{1000000 + n},{n},,800.")
    lines.append("ENDDATA")
    path.write_text("\n".join(lines) + "\n")
    return nid


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", choices=SIZES, default="full")
    args = p.parse_args(argv)

    from cpylog import SimpleLogger
    from pyNastran.bdf.bdf import BDF

    from eigenupdate.io.nastran import CardField, read_nastran
    from eigenupdate.model.parameters import Parameter

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "frame.bdf"
        t0 = time.perf_counter()
        n_grids = write_frame(path, *SIZES[args.size])
        t_write = time.perf_counter() - t0
        print(f"frame BDF: {n_grids} grids, {path.stat().st_size / 1e6:.1f} MB "
              f"(written in {t_write:.1f} s)")
        t0 = time.perf_counter()
        BDF(log=SimpleLogger(level="critical")).read_bdf(str(path), xref=False)
        t_base = time.perf_counter() - t0
        fields = [(Parameter(f"{f}_{m}", 0.0), CardField("MAT1", i, f))
                  for i, m in ((1, "columns"), (2, "beams")) for f in ("E", "RHO")]
        t0 = time.perf_counter()
        nm = read_nastran(path, fields)
        t_ours = time.perf_counter() - t0
    m = nm.model
    print(f"model: {m.n} free coordinates, K0 + {len(m.parameters)} parameter terms, "
          f"nnz(K) = {m.stiffness().nnz}")
    print(f"baseline, pyNastran read_bdf alone:        {t_base:7.2f} s")
    print(f"read_nastran (read + validate + assemble): {t_ours:7.2f} s")
    print(f"ratio: {t_ours / t_base:.2f} (assembly and validation add "
          f"{t_ours - t_base:.2f} s)")


if __name__ == "__main__":
    main()
