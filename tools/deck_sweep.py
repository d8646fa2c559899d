"""Sweep every NASTRAN bulk-data deck under a folder through ``read_nastran`` (issue 20).

Usage (in the NASTRAN venv, from the repository root)::

    PYTHONPATH=src python tools/deck_sweep.py FOLDER [--timeout 60] [--max-grids 200000]
        [-k SUBSTRING] [--no-compare]

Each deck (.bdf .dat .nas .blk .pch .inc, except files another deck INCLUDEs and files with
no GRID, SPOINT or DMIG card) is read in its own subprocess, one after the other (60 s each,
2 GB address space). Outcomes: ``ok``; ``refused`` (an :class:`InputError`, grouped by the
kind of message: one group per unsupported card, otherwise the message with its numbers and
names blanked); ``crashed`` (any other exception: a bug); ``timeout``; ``skipped`` (over
``--max-grids`` GRID lines).

When a deck reads and NASTRAN's eigenvalues of it are beside it (the .f06's REAL EIGENVALUES
table - the second with QSET, the first being the fixed-interface modes - else the .op2's
LAMA table, same stem), the deck is solved for as many modes as
NASTRAN printed and the elastic frequencies compared (NASTRAN's rows after as many rows as
we find rigid-body modes): the largest relative difference is listed with the tolerance
(1 % with shells or solids, 1e-4 with line, spring, mass and rigid cards only).
"""

from __future__ import annotations

import argparse
import json
import re
import resource
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

EXTENSIONS = {".bdf", ".dat", ".nas", ".blk", ".pch", ".inc", ".inp"}  # .inp: NASTRAN-95
_INCLUDE = re.compile(r"^\s*INCLUDE\s+'?([^'$]+)'?", re.IGNORECASE)
_MODEL_CARD = re.compile(r"^(GRID|SPOINT|DMIG)[\s,*]", re.IGNORECASE)
_GRID = re.compile(r"^GRID[\s,*]", re.IGNORECASE)
# cards that make a deck's reference a shell/solid one (formulations differ: 1 %)
CONTINUUM = ("CQUAD", "CTRIA", "CSHEAR", "CHEXA", "CPENTA", "CTETRA", "CPYRAM")


def decks(folder: Path) -> tuple[list[Path], list[Path]]:
    """(decks, include-only fragments) under ``folder``."""
    from eigenupdate.io.nastran_include import local_name

    files = sorted(p for p in folder.rglob("*") if p.is_file()
                   and p.suffix.lower() in EXTENSIONS)
    included: set[Path] = set()
    for p in files:
        for line in p.read_text(errors="replace").splitlines():
            m = _INCLUDE.match(line)
            if m:
                included.add((p.parent / local_name(m.group(1).strip())).resolve())
    main, fragments = [], []
    for p in files:
        text = p.read_text(errors="replace").splitlines()
        has_model = any(_MODEL_CARD.match(x) for x in text)
        has_include = any(_INCLUDE.match(x) for x in text)
        if p.resolve() in included or not (has_model or has_include):
            fragments.append(p)
        else:
            main.append(p)
    return main, fragments


def grid_lines(path: Path) -> int:
    with path.open(errors="replace") as f:
        return sum(1 for line in f if _GRID.match(line))


def f06_table(path: Path, skip: int = 0) -> list[float] | None:
    """The first subcase's REAL EIGENVALUES (Hz), across page breaks: the rows numbered
    1, 2, 3, ... after the first such header; with ``skip``, the table after as many
    tables (a QSET deck's first is its fixed-interface modes)."""
    rows: list[float] = []
    inside = False
    for line in path.read_text(errors="replace").splitlines():
        if "R E A L   E I G E N V A L U E S" in line:
            inside = True
            continue
        parts = line.split()
        if inside and len(parts) == 7 and parts[0].isdigit() and parts[1].isdigit():
            if int(parts[0]) == 1 and rows and skip > 0:  # the next table begins
                rows, skip = [], skip - 1
            if int(parts[0]) != len(rows) + 1:  # another subcase's table
                break
            try:
                rows.append(float(parts[4]))
            except ValueError:
                break
    return rows if rows and not skip else None


def op2_table(path: Path) -> list[float] | None:
    """The first LAMA table (Hz) of an .op2 (None without one or if unreadable)."""
    if path.stat().st_size > 200e6:
        return None
    try:
        from pyNastran.op2.op2 import OP2
        op2 = OP2(debug=False, log=None, mode=None)
        op2.log.level = "critical"
        op2.set_results(["eigenvalues"])
        op2.read_op2(str(path), build_dataframe=False, skip_undefined_matrices=True)
    except Exception:
        return None
    for table in op2.eigenvalues.values():  # not ComplexEigenvalues, BucklingEigenvalues
        if type(table).__name__ == "RealEigenvalues" and len(table.cycles):
            return [float(x) for x in table.cycles]
    return None


def ref_json(deck: Path) -> list[float] | None:
    """``cycles_hz`` of a ref.json beside the deck that names it (``deck``), the layout of
    ../shared/data/nastran/ (NASTRAN's frequencies, rigid-body modes included)."""
    path = deck.parent / "ref.json"
    try:
        ref = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    hz = ref.get("cycles_hz") if isinstance(ref, dict) else None
    if ref.get("deck", deck.name) != deck.name or not isinstance(hz, list) or not hz:
        return None
    return [float(x) for x in hz]


def reference(deck: Path, skip: int = 0) -> tuple[str, list[float]] | None:
    """NASTRAN's eigenvalue table of a deck: (file name, Hz) from a ref.json that names
    it, else the .f06, else the .op2; ``skip`` tables of the .f06 first (the .op2 is not
    read then)."""
    hz = ref_json(deck)
    if hz:
        return "ref.json", hz
    readers = [(".f06", lambda p: f06_table(p, skip))]
    if not skip:
        readers.append((".op2", op2_table))
    for suffix, reader in readers:
        for p in deck.parent.iterdir():
            if p.stem.lower() == deck.stem.lower() and p.suffix.lower() == suffix:
                hz = reader(p)
                if hz:
                    return p.name, hz
    return None


def one(path: Path, compare: bool) -> dict:
    """Read (and compare) one deck; the child process's work."""
    import warnings

    import numpy as np

    from eigenupdate.errors import InputError
    from eigenupdate.io.nastran import read_nastran
    from eigenupdate.io.nastran_solution import BUCKLING, solution
    from eigenupdate.solve.eigen import solve_elastic

    out: dict = {"deck": str(path)}
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            nm = read_nastran(path)
    except InputError as exc:
        out.update(status="refused", message=str(exc))
        return out
    except Exception as exc:  # a bug: any failure that is not a clear refusal
        import traceback
        tb = traceback.extract_tb(exc.__traceback__)
        frame = next((f for f in reversed(tb) if "eigenupdate" in f.filename), tb[-1])
        out.update(status="crashed", message=f"{type(exc).__name__}: {exc}".splitlines()[0],
                   where=f"{Path(frame.filename).name}:{frame.lineno}")
        return out
    out.update(status="ok", seconds=round(time.perf_counter() - t0, 2),
               n=len(nm.model.coordinates))
    # a dynamic reduction's (QSET) first table is its fixed-interface modes
    ref = reference(path, 1 if nm.modal else 0) if compare else None
    if ref is None:
        return out
    name, hz = ref
    cend = next((i for i, x in enumerate(nm.text) if x.upper().strip().startswith("CEND")), -1)
    if solution(nm.text, cend)[0] in BUCKLING:  # its table holds load factors
        out.update(reference=name, compare="a buckling deck: no frequencies to compare")
        return out
    cards = set(nm.bdf.elements) and {e.type for e in nm.bdf.elements.values()}
    continuum = any(c.startswith(CONTINUUM) for c in cards)
    out.update(reference=name, tolerance=1e-2 if continuum else 1e-4)
    try:
        model = nm.model
        K, M = model.stiffness(), model.mass()
        n_rigid = solve_elastic(K, M, 1).n_rigid
        # NASTRAN's rigid-body rows: ours, and any leading exact zeros (a free massless
        # coordinate NASTRAN keeps and we condense)
        top = max(abs(x) for x in hz)
        skip = n_rigid
        while skip < len(hz) and abs(hz[skip]) <= 1e-9 * top:
            skip += 1
        v2, nd = eigrl(nm.text)
        # rows beyond EIGRL ND or above V2: SOL 111/112 residual vectors (RESVEC)
        rows = np.array(hz[:nd] if nd else hz)
        if v2 is not None:
            rows = rows[rows <= v2 * (1 + 1e-6)]
        above = len(hz) - len(rows)
        theirs = rows[skip:]
        k = min(len(theirs), len(model.coordinates) - n_rigid)
        if k <= 0:
            out.update(compare="no elastic modes to compare")
            return out
        ours = solve_elastic(K, M, k).frequencies_hz
        err = ours[:k] / theirs[:k] - 1
        worst = int(np.argmax(np.abs(err)))
        out.update(compare="ok", modes=k, n_rigid=int(n_rigid), rigid_ref=hz[:skip],
                   above_v2=above, worst=float(err[worst]), worst_mode=worst + 1 + skip,
                   ours=[float(x) for x in ours[:k]], theirs=[float(x) for x in theirs[:k]])
    except Exception as exc:
        out.update(compare=f"solve failed: {type(exc).__name__}: {exc}".splitlines()[0])
    return out


_METHOD = re.compile(r"^\s*METHOD\s*(\([^)]*\))?\s*=\s*(\d+)", re.IGNORECASE)


def _fields(line: str) -> list[str]:
    if "," in line:
        return [x.strip() for x in line.split(",")]
    return [line[i:i + 8].strip() for i in range(0, min(len(line), 72), 8)]


def eigrl(text: list[str]) -> tuple[float | None, int | None]:
    """V2 (Hz) and ND of the EIGRL the case control selects: Lanczos finds no more than
    ND eigenvalues (rigid-body ones included) and none above V2, so NASTRAN's rows
    beyond are residual vectors. An EIGR's ND for FEER only (the other methods' rows
    beyond ND are accurate eigenvalues; EIGR's F2 bounds only the eigenvectors of its
    tridiagonal methods): NASTRAN-95's FEER prints unconverged approximations beyond the
    ND roots it was asked for (D03-01-2A: ND 1, 12 rows, the last six 2-72 % off)."""
    methods = {int(m.group(2)) for m in map(_METHOD.match, text) if m}
    for line in text:
        f = _fields(line)
        card = f[0].upper().rstrip("*") if f else ""
        if len(f) < 4 or card not in ("EIGRL", "EIGR"):
            continue
        try:
            if methods and int(f[1]) not in methods:
                continue
            if card == "EIGR":  # GIV, HOU, INV... print accurate rows beyond ND
                feer = f[2].upper() == "FEER" and len(f) > 6 and f[6]
                return None, (int(f[6]) if feer else None)
            v2 = float(f[3].replace("D", "E")) if f[3] else None
            nd = int(f[4]) if len(f) > 4 and f[4] else None
            return v2, nd
        except ValueError:
            continue
    return None, None


def _limit() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))


def kinds(message: str) -> list[str]:
    """The refusal's kind(s): one per unsupported card, else the message made generic."""
    m = re.search(r"not supported: (.*)$", message)
    if m:
        return [f"card {c.split(' x')[0].strip()} not supported"
                for c in m.group(1).split(", ") if c.strip()]
    text = re.sub(r"^.*?\.(bdf|dat|nas|blk|pch|inc|f06)(:\d+)?: ", "", message,
                  flags=re.IGNORECASE)
    text = re.sub(r"^[\w.+-]+:\d+: ", "", text)
    text = re.sub(r"-?\d+(\.\d*)?([eE][-+]?\d+)?", "N", text)
    text = re.sub(r"'[^']*'", "'...'", text)
    return [text[:90]]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", type=Path, nargs="?")
    ap.add_argument("--timeout", type=float, default=60)
    ap.add_argument("--max-grids", type=int, default=200_000)
    ap.add_argument("-k", default="", help="only decks whose path contains this")
    ap.add_argument("--no-compare", action="store_true")
    ap.add_argument("--json", type=Path, help="also write every result to this file")
    ap.add_argument("--one", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(one(args.one, not args.no_compare)))
        return 0
    if args.folder is None:
        ap.error("a folder is required")
    found, fragments = decks(args.folder)
    found = [p for p in found if args.k in str(p)]
    results = []
    for p in found:
        rel = str(p.relative_to(args.folder))
        if grid_lines(p) > args.max_grids:
            results.append({"deck": rel, "status": "skipped", "message": "too many GRIDs"})
            continue
        cmd = [sys.executable, __file__, "--one", str(p)]
        if args.no_compare:
            cmd.append("--no-compare")
        try:
            run = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout,
                                 preexec_fn=_limit)
            last = run.stdout.strip().splitlines()[-1] if run.stdout.strip() else ""
            r = json.loads(last) if last.startswith("{") else {
                "status": "crashed", "message": (run.stderr.strip().splitlines() or ["?"])[-1]}
        except subprocess.TimeoutExpired:
            r = {"status": "timeout", "message": f"over {args.timeout:g} s"}
        r["deck"] = rel
        results.append(r)
        print(f"{r['status']:8s} {rel}  {r.get('message', '')[:150]}", flush=True)
    _table(results, len(fragments))
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))
    return 0


def _table(results: list[dict], n_fragments: int) -> None:
    status = Counter(r["status"] for r in results)
    print(f"\n{len(results)} decks ({n_fragments} include-only fragments skipped): "
          + ", ".join(f"{k} {v}" for k, v in sorted(status.items())))
    for what in ("refused", "crashed"):
        groups: Counter = Counter()
        for r in results:
            if r["status"] == what:
                groups.update(set(kinds(r["message"]) if what == "refused"
                                  else [f"{r['message'][:90]} ({r.get('where', '')})"]))
        if groups:
            print(f"\n{what} (decks per kind):")
            for k, v in groups.most_common():
                print(f"  {v:4d}  {k}")
    compared = [r for r in results if r.get("compare")]
    if compared:
        print("\nagreement with NASTRAN's eigenvalues (elastic modes, relative):")
        for r in compared:
            if r["compare"] != "ok":
                print(f"  {r['deck']}: {r['compare']}")
                continue
            flag = "AGREES" if abs(r["worst"]) <= r["tolerance"] else "DIFFERS"
            extra = f", {r['above_v2']} rows beyond EIGRL ND/V2 left out" if r["above_v2"] else ""
            print(f"  {flag:8s} {r['deck']} vs {r['reference']}: {r['modes']} modes, "
                  f"{r['n_rigid']} rigid, worst {r['worst']:+.2e} (mode {r['worst_mode']}), "
                  f"tolerance {r['tolerance']:g}{extra}")


if __name__ == "__main__":
    sys.exit(main())
