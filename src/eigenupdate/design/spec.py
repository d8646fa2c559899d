"""The ``[design]`` table of a study: what the planner may choose from and how it judges."""

from __future__ import annotations

from dataclasses import dataclass

CRITERIA = ("A", "D", "E")


@dataclass(frozen=True)
class DesignSpec:
    """Candidate perturbations, constraints and criterion of a test plan.

    Attributes
    ----------
    coordinates : candidate coordinates (user numbers), validated against the model.
    masses : added masses to choose from, kg (kg m^2 on rotational coordinates).
    stiffnesses : grounded springs to choose from, N/m (may be empty).
    configurations : number of perturbed configurations in the plan (besides the bare one).
    additions : largest number of additions in one configuration (at distinct coordinates).
    modes : elastic modes that can be measured, or None to take every mode of the bare
        structure below ``max_frequency_hz``.
    max_frequency_hz : highest frequency that can be measured, Hz (when ``modes`` is None).
    frequency_std_hz : measurement std of each mode (one value per mode), or None.
    frequency_std_relative : measurement std as a fraction of the frequency, or None.
    criterion : "A", "D", "E", or a tuple of parameter names (sum of their normalised
        posterior variances).
    min_shift_in_std : every chosen perturbation shifts at least one used mode by more than
        this many measurement std.
    min_relative_gap : every used mode of a chosen configuration stays this far (relative,
        in frequency) from its neighbouring modes.
    max_added_mass : largest total mass added in one configuration, kg, or None.
    prior_draws : draws of the truth from the prior over which the criterion and the
        predicted accuracy are averaged (:mod:`eigenupdate.design.prior`); 0: judge at
        the prior mean only (also when a parameter has no prior std).
    max_exchange_risk : largest fraction of the draws in which a chosen candidate may
        reorder a used mode or bring it within ``min_relative_gap`` of another.
    labels : (coordinate, label) pairs naming coordinates in the candidates' names where
        the model has its own convention (NASTRAN: "7-2" for grid 7, component 2); the
        others are named by their number.
    """

    coordinates: tuple[int, ...]
    masses: tuple[float, ...]
    configurations: int
    modes: tuple[int, ...] | None
    max_frequency_hz: float | None = None
    frequency_std_hz: tuple[float, ...] | None = None
    frequency_std_relative: float | None = None
    stiffnesses: tuple[float, ...] = ()
    additions: int = 1
    criterion: str | tuple[str, ...] = "A"
    min_shift_in_std: float = 3.0
    min_relative_gap: float = 0.02
    max_added_mass: float | None = None
    prior_draws: int = 64
    max_exchange_risk: float = 0.05
    labels: tuple[tuple[int, str], ...] = ()

    @property
    def values(self) -> int:
        """Added masses and springs to choose from at each coordinate."""
        return len(self.masses) + len(self.stiffnesses)
