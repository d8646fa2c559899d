"""The names the command line offers as choices, in a module that imports nothing, so that
``eigenupdate --help`` needs none of the modules that use them."""

ESTIMATORS = ("least-squares", "weighted-least-squares", "bayesian")
"""The estimators :func:`eigenupdate.identify.updating.update` offers."""
OPTIMIZERS = ("trust-region", "gauss-newton")
"""Its optimisers."""
FRF_KINDS: tuple[str, str, str] = ("receptance", "mobility", "accelerance")
"""FRF kinds accepted by :func:`eigenupdate.measure.frf.to_receptance`."""
SCHEDULER_ENV = "EIGENUPDATE_SCHEDULER"
"""Environment variable with the address of an existing Dask scheduler (tcp://host:port)."""
