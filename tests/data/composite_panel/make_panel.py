"""Writes the composite-panel test decks (run from this directory): a copy of
examples/stiffened_panel/make_panel.py made smaller, its skin a laminate.

mesh.bdf   GRID, CQUAD4, SPC1: a 0.6 m x 0.4 m skin (12 x 8 CQUAD4, PCOMP 1: LAM=SYM
           [0/45/-45/90]s of MAT8 1, carbon-epoxy) with two aluminium blade stiffeners
           along x at y = 0.1 and 0.3 m, 30 mm high (2 x 12 CQUAD4 each, PSHELL 2 of
           MAT1 2), both short edges (x = 0, 0.6) clamped.
panel.bdf  the model to update: the ply's nominal E1 and G12, INCLUDE 'mesh.bdf'.
truth.bdf  the same mesh with the E1 and G12 that simulate the test.
"""

import importlib.util
from pathlib import Path

# the shipped example's mesh generator, on a coarser grid (loaded by path: this file has
# the same name)
_spec = importlib.util.spec_from_file_location(
    "stiffened_panel_mesh",
    Path(__file__).resolve().parents[3] / "examples" / "stiffened_panel" / "make_panel.py")
_example = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_example)


def mesh() -> str:
    return _example.mesh(12, 8, (2, 6), "composite stiffened panel: skin PCOMP 1, blades "
                                        "PSHELL 2")


def header(title: str, e1: str, g12: str) -> str:
    return (f"$ {title}\nSOL 103\nCEND\nSPC = 1\nBEGIN BULK\nPARAM,COUPMASS,1\n"
            f"PCOMP,1,,,,,,,SYM\n,1,0.00025,0.,,1,0.00025,45.\n"
            f",1,0.00025,-45.,,1,0.00025,90.\n"
            f"MAT8,1,{e1},1.0e10,0.3,{g12},5.0e9,3.0e9,1600.\n"
            f"PSHELL,2,2,0.003,2,,2\nMAT1,2,7.0e10,,0.33,2700.\n"
            f"INCLUDE 'mesh.bdf'\nENDDATA\n")


if __name__ == "__main__":
    Path("mesh.bdf").write_text(mesh())
    Path("panel.bdf").write_text(header("composite panel: nominal values", "1.4e11", "5.0e9"))
    Path("truth.bdf").write_text(header("composite panel: truth (simulates the test)",
                                        "1.32e11", "4.6e9"))
