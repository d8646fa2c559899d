"""The hostile-case tables of tools/ (rounds 1-5) hold no row twice: the same command
on the same example, mutated by the same code with the same constants, is one case
(round 2 repeated round 1's `montecarlo --workers 0`)."""

import importlib.util
import sys

from conftest import ROOT


def _key(f):
    """What a mutation does, as far as its code and constants tell."""
    if f is None:
        return None
    cells = tuple(_key(c.cell_contents) if callable(c.cell_contents) else repr(c.cell_contents)
                  for c in (f.__closure__ or ()))
    return (f.__code__.co_code, repr(f.__code__.co_consts), f.__code__.co_names, cells,
            repr(f.__defaults__))


def test_no_hostile_case_is_repeated():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import hostile

        rows = {"hostile.py": list(hostile.CASES)}
        for n in (2, 3, 4, 5):
            spec = importlib.util.spec_from_file_location(
                f"hostile_round{n}", ROOT / "tools" / f"hostile_round{n}.py")
            spec.loader.exec_module(importlib.util.module_from_spec(spec))
            rows[f"round {n}"] = list(hostile.CASES)  # each round clears the table
    finally:
        sys.path.remove(str(ROOT / "tools"))
    seen: dict = {}
    repeats = []
    for table, cases in rows.items():
        for name, example, argv, mutate, python, env, _check in cases:
            key = (example, tuple(map(str, argv)), _key(mutate), python, repr(env))
            if key in seen:
                repeats.append((seen[key], f"{table}: {name}"))
            seen.setdefault(key, f"{table}: {name}")
    assert not repeats, repeats
    assert len(rows["round 4"]) >= 15
    assert len(rows["round 5"]) >= 40
