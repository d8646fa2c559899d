"""Universal file (UFF) input/output, one module per dataset type: FRFs (dataset 58 / 58b,
:mod:`.dataset58`) and normal modes (dataset 55, :mod:`.dataset55`), through pyuff
(:mod:`._pyuff`)."""

from eigenupdate.io.uff.dataset55 import read_modes, write_modes
from eigenupdate.io.uff.dataset58 import read_frfs, write_frfs

__all__ = ["read_frfs", "read_modes", "write_frfs", "write_modes"]
