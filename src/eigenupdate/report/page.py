"""The structure of the HTML report's page: sections of paragraphs, key facts, tables
(cells as text, numbers marked) and figures inlined as SVG ``data:`` URIs."""

from __future__ import annotations

import base64
import io
import math
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from eigenupdate.io.atomic import scratch


@dataclass
class Table:
    """A real HTML table: header cells and rows of (text, is_number) cells."""

    caption: str
    header: list[str]
    rows: list[list[tuple[str, bool]]]
    name: str = ""  # data-name attribute, for tests and styling
    kind: str = "table"


@dataclass
class Image:
    """A figure as a ``data:`` URI."""

    uri: str
    caption: str
    alt: str
    kind: str = "image"


@dataclass
class Section:
    """One section of the page: paragraphs, key facts, then tables and figures in order."""

    id: str
    title: str
    paragraphs: list[str] = field(default_factory=list)
    facts: list[tuple[str, str]] = field(default_factory=list)
    blocks: list[Table | Image] = field(default_factory=list)
    parts: list[Section] = field(default_factory=list)  # sub-sections (one per configuration)


def cell(v: Any) -> tuple[str, bool]:
    if v is None:
        return ("-", False)
    if isinstance(v, bool):
        return ("yes" if v else "no", False)
    if isinstance(v, int | np.integer):
        return (str(int(v)), True)
    if isinstance(v, float | np.floating):
        return (f"{float(v):.6g}" if math.isfinite(v) else "-", math.isfinite(v))
    return (str(v), False)


def table(caption: str, header: Sequence[str], rows: Sequence[Sequence[Any]],
           name: str = "") -> Table:
    return Table(caption, list(header), [[cell(v) for v in r] for r in rows], name)


def svg_uri(data: bytes) -> str:
    return "data:image/svg+xml;base64," + base64.b64encode(data).decode("ascii")


# Text as SVG text (not glyph outlines): a third smaller, and searchable in the PDF.
_SVG_RC = {"svg.fonttype": "none", "svg.hashsalt": "eigenupdate"}


def figure_image(fig: Figure, caption: str, alt: str) -> Image:
    buf = io.BytesIO()
    with matplotlib.rc_context(_SVG_RC):
        fig.savefig(buf, format="svg")
    return Image(svg_uri(buf.getvalue()), caption, alt)


def plot_image(plot: Callable[..., Any], caption: str, alt: str, *args: Any,
                **kwargs: Any) -> tuple[Image, Any]:
    """Run one of :mod:`eigenupdate.plot.plots` into a temporary SVG and inline it."""
    with tempfile.TemporaryDirectory() as tmp, matplotlib.rc_context(_SVG_RC), scratch():
        path = Path(tmp) / "figure.svg"
        out = plot(path, *args, **kwargs)
        return Image(svg_uri(path.read_bytes()), caption, alt), out
