"""Writes the stiffened-panel example's decks (run from this directory).

mesh.bdf   GRID, CQUAD4, SPC1: a 0.6 m x 0.4 m aluminium skin (24 x 16 CQUAD4, PSHELL 1)
           with two blade stiffeners along x at y = 0.1 and 0.3 m, 30 mm high
           (2 x 24 CQUAD4 each, PSHELL 2), both short edges (x = 0, 0.6) clamped.
panel.bdf  the model to update: nominal thicknesses and modulus, INCLUDE 'mesh.bdf'.
truth.bdf  the same mesh with the values that simulate the test (see README.md).
"""

from pathlib import Path

LX, LY, NX, NY = 0.6, 0.4, 24, 16
BLADE_ROWS, BLADE_H, NZ = (4, 12), 0.03, 2


def grid_id(i, j, k=0):
    """Skin grid (i along x, j along y): 1000 j + i + 1; blade grid k above it: + 100000 k."""
    return 100000 * k + 1000 * j + i + 1


def mesh(nx: int = NX, ny: int = NY, blade_rows: tuple = BLADE_ROWS,
         title: str = "stiffened panel: skin PSHELL 1, blades PSHELL 2") -> str:
    """The mesh of ``nx`` x ``ny`` skin CQUAD4 (PID 1) with blades (PID 2) along x at
    the skin rows ``blade_rows`` (tests/data/composite_panel uses a coarser one)."""
    lines = [f"$ {title}"]
    for j in range(ny + 1):
        for i in range(nx + 1):
            lines.append(f"GRID,{grid_id(i, j)},,{LX * i / nx:.6f},{LY * j / ny:.6f},0.")
    for j in blade_rows:
        for k in range(1, NZ + 1):
            for i in range(nx + 1):
                lines.append(f"GRID,{grid_id(i, j, k)},,{LX * i / nx:.6f},{LY * j / ny:.6f},"
                             f"{BLADE_H * k / NZ:.6f}")
    eid = 1
    for j in range(ny):
        for i in range(nx):
            g = (grid_id(i, j), grid_id(i + 1, j), grid_id(i + 1, j + 1), grid_id(i, j + 1))
            lines.append(f"CQUAD4,{eid},1," + ",".join(map(str, g)))
            eid += 1
    for j in blade_rows:
        for k in range(NZ):
            for i in range(nx):
                g = (grid_id(i, j, k), grid_id(i + 1, j, k), grid_id(i + 1, j, k + 1),
                     grid_id(i, j, k + 1))
                lines.append(f"CQUAD4,{eid},2," + ",".join(map(str, g)))
                eid += 1
    edge = [grid_id(i, j) for i in (0, nx) for j in range(ny + 1)]
    edge += [grid_id(i, j, k) for i in (0, nx) for j in blade_rows for k in range(1, NZ + 1)]
    lines += [f"SPC1,1,123456,{g}" for g in edge]
    return "\n".join(lines) + "\n"


def header(title: str, t_skin: str, t_blade: str, e: str) -> str:
    return (f"$ {title}\nSOL 103\nCEND\nSPC = 1\nBEGIN BULK\nPARAM,COUPMASS,1\n"
            f"PSHELL,1,1,{t_skin},1,,1\nPSHELL,2,1,{t_blade},1,,1\n"
            f"MAT1,1,{e},,0.33,2700.\nINCLUDE 'mesh.bdf'\nENDDATA\n")


if __name__ == "__main__":
    Path("mesh.bdf").write_text(mesh())
    Path("panel.bdf").write_text(header("stiffened panel: nominal values", "0.002", "0.003",
                                        "7.0e10"))
    Path("truth.bdf").write_text(header("stiffened panel: truth (simulates the test)",
                                        "0.00215", "0.0028", "7.25e10"))
