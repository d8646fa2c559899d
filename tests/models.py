"""Small models shared by the tests."""

import numpy as np

from eigenupdate.model.beam import beam_model
from eigenupdate.model.parameters import Parameter
from eigenupdate.model.spring_mass import Mass, Spring, spring_mass_model

FIG2_SPRINGS = [(0, 1), (1, 2), (2, 3), (0, 3), (2, 4), (0, 4)]


def fig2(k=(1.2e6, 1.2e6, 1.2e6, 0.95e6, 0.96e6, 0.6e6), m=(9.7, 9.7, 4.7, 4.7)):
    return spring_mass_model(
        [Mass(Parameter(f"m{i + 1}", m[i]), i + 1) for i in range(4)],
        [Spring(Parameter(f"k{i + 1}", k[i]), FIG2_SPRINGS[i]) for i in range(6)],
    )


def paper_beam(**kw):
    return beam_model(
        [0.0, 0.09, 0.19, 0.29, 0.39, 0.49, 0.59, 0.69, 0.80], 4557.0, 3.4,
        EI_std=150.0, mass_per_length_std=0.1,
        point_masses=[(Parameter("m_L", 0.02, std=0.1), 11), (Parameter("J4", 1e-4), 8)], **kw,
    )


def random_network(rng, n):
    """Connected chain plus random extra springs, at least one to ground."""
    masses = [Mass(Parameter(f"m{i}", rng.uniform(1, 10)), i) for i in range(1, n + 1)]
    pairs = [(i, i + 1) for i in range(1, n)] + [(0, int(rng.integers(1, n + 1)))]
    for _ in range(int(rng.integers(0, n))):
        a, b = sorted(rng.choice(np.arange(0, n + 1), 2, replace=False).tolist())
        if (a, b) not in pairs:
            pairs.append((a, b))
    springs = [Spring(Parameter(f"k{j}", rng.uniform(0.5e6, 2e6)), p)
               for j, p in enumerate(pairs, 1)]
    return spring_mass_model(masses, springs, n)
