"""Writes the composite-panel test decks (run from this directory): a copy of
examples/stiffened_panel/make_panel.py made smaller, its skin a laminate.

mesh.bdf   GRID, CQUAD4, SPC1: a 0.6 m x 0.4 m skin (12 x 8 CQUAD4, PCOMP 1: LAM=SYM
           [0/45/-45/90]s of MAT8 1, carbon-epoxy) with two aluminium blade stiffeners
           along x at y = 0.1 and 0.3 m, 30 mm high (2 x 12 CQUAD4 each, PSHELL 2 of
           MAT1 2), both short edges (x = 0, 0.6) clamped.
panel.bdf  the model to update: the ply's nominal E1 and G12, INCLUDE 'mesh.bdf'.
truth.bdf  the same mesh with the E1 and G12 that simulate the test.
"""

from pathlib import Path

LX, LY, NX, NY = 0.6, 0.4, 12, 8
BLADE_ROWS, BLADE_H, NZ = (2, 6), 0.03, 2


def grid_id(i, j, k=0):
    """Skin grid (i along x, j along y): 1000 j + i + 1; blade grid k above it: + 100000 k."""
    return 100000 * k + 1000 * j + i + 1


def mesh() -> str:
    lines = ["$ composite stiffened panel: skin PCOMP 1, blades PSHELL 2"]
    for j in range(NY + 1):
        for i in range(NX + 1):
            lines.append(f"GRID,{grid_id(i, j)},,{LX * i / NX:.6f},{LY * j / NY:.6f},0.")
    for j in BLADE_ROWS:
        for k in range(1, NZ + 1):
            for i in range(NX + 1):
                lines.append(f"GRID,{grid_id(i, j, k)},,{LX * i / NX:.6f},{LY * j / NY:.6f},"
                             f"{BLADE_H * k / NZ:.6f}")
    eid = 1
    for j in range(NY):
        for i in range(NX):
            g = (grid_id(i, j), grid_id(i + 1, j), grid_id(i + 1, j + 1), grid_id(i, j + 1))
            lines.append(f"CQUAD4,{eid},1," + ",".join(map(str, g)))
            eid += 1
    for j in BLADE_ROWS:
        for k in range(NZ):
            for i in range(NX):
                g = (grid_id(i, j, k), grid_id(i + 1, j, k), grid_id(i + 1, j, k + 1),
                     grid_id(i, j, k + 1))
                lines.append(f"CQUAD4,{eid},2," + ",".join(map(str, g)))
                eid += 1
    edge = [grid_id(i, j) for i in (0, NX) for j in range(NY + 1)]
    edge += [grid_id(i, j, k) for i in (0, NX) for j in BLADE_ROWS for k in range(1, NZ + 1)]
    lines += [f"SPC1,1,123456,{g}" for g in edge]
    return "\n".join(lines) + "\n"


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
