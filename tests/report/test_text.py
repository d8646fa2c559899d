"""The command line's text tables keep the numbers they print."""

import numpy as np

from eigenupdate.report.text import frequencies_text


def test_frequency_table_keeps_six_significant_digits_of_any_size():
    """A hostile deck (1e-60 m shells) gave 5.75e-78 Hz, which the table printed as 0
    (rounded to 4 decimals); a 1e5 m structure's 3.2e-5 Hz alike. Source of the check:
    the values themselves, read back from the table within 6 significant digits."""
    freqs = {"base": np.array([5.75e-78, 3.2e-5, 12.3456789, 98765.4321])}
    text = frequencies_text(freqs, "deck.bdf")
    row = text.splitlines()[-1].split()
    assert row[0] == "base"
    back = np.array([float(x) for x in row[1:]])
    assert np.all(np.abs(back / freqs["base"] - 1) <= 5e-6)
