"""eigenupdate: update FE model parameters from natural frequencies of the bare and
mass- or stiffness-perturbed structure (mass-addition model updating)."""

from eigenupdate.errors import InputError

__all__ = ["InputError"]
__version__ = "0.1.0"
