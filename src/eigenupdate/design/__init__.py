"""Test planning: choose the added masses before the lab (``eigenupdate design``) and check a
plan by virtual tests (``eigenupdate montecarlo``)."""
