"""Small models shared by the tests."""

import numpy as np

from eigenupdate.model.beam import beam_model
from eigenupdate.model.configurations import Configuration, mass_at
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


def thickness_strip(n_el=8, E=70e9, t=(0.004, 0.005), rho=2700.0, width=0.05, length=0.8,
                    std=None):
    """A free-free rectangular strip in bending, E and the thicknesses t1 (first half of
    the elements), t2 (second half) its parameters: EI = E b t^3 / 12 (a product E t^3),
    mass per length rho b t. Built from the unit-EI, unit-mass beam elements of
    :func:`beam_model`; returns (nonlinear model, the unit linear beam)."""
    from eigenupdate.model.parametric import ParametricModel, Term

    unit = beam_model(np.linspace(0.0, length, n_el + 1).tolist(), 1.0, 1.0)
    params = (Parameter("E", E, None if std is None else std * E),
              Parameter("t1", t[0], None if std is None else std * t[0]),
              Parameter("t2", t[1], None if std is None else std * t[1]))
    region = [1 if e < n_el // 2 else 2 for e in range(n_el)]
    kp = [Term(unit.k_terms[e], ((0, 1.0), (region[e], 3.0)), width / 12) for e in range(n_el)]
    mp = [Term(unit.m_terms[n_el + e], ((region[e], 1.0),), rho * width) for e in range(n_el)]
    model = ParametricModel.from_parts(unit.k0, unit.m0, params, kp, mp, unit.coordinates,
                                       unit.coordinate_table)
    return model, unit


PAIRING_CONFIGS = [Configuration("base")] + [mass_at(c, 0.15, f"at {c}") for c in (1, 2, 3, 4)]
PAIRING_MODES = [1, 2, 3, 4]


def chains(kA, kB, mA=(1.0, 1.0), mB=(1.0, 1.0)):
    """Two chains ground-k-m-k-m that are not coupled: their modes cross exactly."""
    ms = [Mass(Parameter(f"mA{i + 1}", mA[i]), i + 1) for i in range(2)] + \
         [Mass(Parameter(f"mB{i + 1}", mB[i]), i + 3) for i in range(2)]
    ks = [Spring(Parameter("kA1", kA[0]), (0, 1)), Spring(Parameter("kA2", kA[1]), (1, 2)),
          Spring(Parameter("kB1", kB[0]), (0, 3)), Spring(Parameter("kB2", kB[1]), (3, 4))]
    return spring_mass_model(ms, ks, 4)


def swapped_case(seed):
    """Truth and a start within 5 % whose modes come in another order in one
    configuration (found by the MAC of the order-paired shapes, below)."""
    rng = np.random.default_rng(seed)
    truth = chains((1e5, 1e5 * rng.uniform(0.9, 1.1)), (1.02e5, 1e5 * rng.uniform(0.9, 1.1)))
    start = truth.with_values(truth.values * rng.uniform(0.95, 1.05, 8))
    return truth, start
