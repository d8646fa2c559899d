"""Open an HTML file in headless Chromium over the DevTools protocol and look at it as a
person would: console errors, requests, loaded images, table rows, a screenshot and the
printed PDF.

Also a command for measuring a report by hand::

    .venv/bin/python tests/_browser.py out/report.html [--screenshot out/shot.png]
"""

from __future__ import annotations

import base64
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--mute-audio"]
INSTALL = "apt-get update && apt-get install -y chromium"


def chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@dataclass
class Page:
    """What the browser saw of one page."""

    load_seconds: float
    errors: list[str]
    requests: list[str]
    images: list[dict]
    tables: list[dict]
    screenshot_png: bytes
    pdf: bytes
    extra: dict = field(default_factory=dict)


class Browser:
    """One headless Chromium with a DevTools websocket to its first tab."""

    def __init__(self, width: int = 1200, height: int = 1600, timeout: float = 60.0):
        import websocket  # websocket-client

        exe = chromium()
        if exe is None:
            raise FileNotFoundError(f"no chromium on PATH; install it: {INSTALL}")
        self._profile = tempfile.TemporaryDirectory(prefix="eigenupdate-chromium-")
        self.proc = subprocess.Popen(
            [exe, *FLAGS, f"--user-data-dir={self._profile.name}",
             "--remote-debugging-port=0", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.timeout = timeout
        port = None
        deadline = time.monotonic() + timeout
        while port is None and time.monotonic() < deadline:
            line = self.proc.stderr.readline()
            if not line and self.proc.poll() is not None:
                raise RuntimeError(f"chromium exited with status {self.proc.returncode}")
            m = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
            port = int(m.group(1)) if m else None
        if port is None:
            self.close()
            raise RuntimeError("chromium did not open its DevTools port")
        # keep reading stderr so that the browser never blocks on a full pipe
        self._drain = subprocess.Popen(["cat"], stdin=self.proc.stderr,
                                       stdout=subprocess.DEVNULL)
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as r:
            tabs = [t for t in json.load(r) if t.get("type") == "page"]
        self.ws = websocket.create_connection(tabs[0]["webSocketDebuggerUrl"],
                                              timeout=timeout, suppress_origin=True)
        self._id = 0
        self.events: list[dict] = []
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(f"{domain}.enable")
        self.call("Emulation.setDeviceMetricsOverride",
                  width=width, height=height, deviceScaleFactor=1, mobile=False)

    def call(self, method: str, **params) -> dict:
        self._id += 1
        self.ws.send(json.dumps({"id": self._id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == self._id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)

    def wait_for(self, method: str) -> dict:
        deadline = time.monotonic() + self.timeout
        while time.monotonic() < deadline:
            for i, e in enumerate(self.events):
                if e.get("method") == method:
                    return self.events.pop(i)
            self.events.append(json.loads(self.ws.recv()))
        raise TimeoutError(method)

    def evaluate(self, expression: str):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True,
                      awaitPromise=True)
        if "exceptionDetails" in r:
            raise RuntimeError(r["exceptionDetails"])
        return r["result"].get("value")

    def open(self, path: Path) -> Page:
        self.events.clear()
        t0 = time.perf_counter()
        self.call("Page.navigate", url=Path(path).resolve().as_uri())
        self.wait_for("Page.loadEventFired")
        load = time.perf_counter() - t0
        images = self.evaluate(
            "Promise.all([...document.images].map(i => i.decode().then(() => true, () => false)"
            ".then(ok => ({alt: i.alt, ok, complete: i.complete, width: i.naturalWidth}))))")
        tables = self.evaluate(
            "[...document.querySelectorAll('table')].map(t => ({name: t.dataset.name || '', "
            "caption: t.caption ? t.caption.textContent : '', "
            "rows: t.tBodies.length ? t.tBodies[0].rows.length : 0}))")
        shot = base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])
        pdf = base64.b64decode(self.call("Page.printToPDF", preferCSSPageSize=True,
                                         printBackground=True)["data"])
        errors, requests = [], []
        for e in self.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.exceptionThrown":
                errors.append(json.dumps(p["exceptionDetails"])[:300])
            elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                errors.append(json.dumps(p.get("args"))[:300])
            elif m == "Log.entryAdded" and p["entry"].get("level") == "error":
                errors.append(p["entry"].get("text", "")[:300])
            elif m == "Network.requestWillBeSent":
                requests.append(p["request"]["url"][:80])
        return Page(load, errors, requests, images, tables, shot, pdf)

    def text_outside(self, svg: str, directory: Path) -> list[dict]:
        """The <text> elements of ``svg`` (inlined in a page, so the browser sets its text
        as the report's <img> does) whose box reaches outside the SVG's own box by more
        than half a pixel: text the figure clips."""
        page = Path(directory) / "figure.html"
        page.write_text("<!DOCTYPE html><html><body style='margin:0'>" + svg + "</body></html>",
                        encoding="utf-8")
        self.call("Page.navigate", url=page.resolve().as_uri())
        self.wait_for("Page.loadEventFired")
        return self.evaluate(
            "(() => { const s = document.querySelector('svg').getBoundingClientRect(); "
            "return [...document.querySelectorAll('svg text')].map(t => { "
            "const b = t.getBoundingClientRect(); return {text: t.textContent.trim(), "
            "left: b.left - s.left, right: s.right - b.right, top: b.top - s.top, "
            "bottom: s.bottom - b.bottom}; }).filter(r => Math.min(r.left, r.right, r.top, "
            "r.bottom) < -0.5); })()")

    def close(self) -> None:
        try:
            self.ws.close()
        except Exception:  # noqa: BLE001 - closing anyway
            pass
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        if getattr(self, "_drain", None) is not None:
            self._drain.wait(timeout=10)
        self._profile.cleanup()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def pixel_std(png: bytes) -> float:
    """Standard deviation of the grey level (0-1) of a PNG: 0 for a blank page."""
    from matplotlib.image import imread

    img = imread(io.BytesIO(png), format="png")
    return float(img[..., :3].mean(axis=-1).std())


def pdf_pages(pdf: bytes) -> int:
    from pypdf import PdfReader

    return len(PdfReader(io.BytesIO(pdf)).pages)


def main(argv: list[str]) -> int:
    path = Path(argv[0])
    with Browser() as b:
        page = b.open(path)
    print(f"{path}: {os.path.getsize(path) / 1024:.0f} kB, loaded in {page.load_seconds:.2f} s")
    print(f"console errors: {len(page.errors)}; requests other than file:/data:: "
          f"{[u for u in page.requests if not u.startswith(('file:', 'data:'))]}")
    broken = [i for i in page.images if not (i["ok"] and i["width"] > 0)]
    print(f"images: {len(page.images)}, broken: {len(broken)}; tables: {len(page.tables)}")
    print(f"screenshot grey-level std: {pixel_std(page.screenshot_png):.3f}; "
          f"PDF pages: {pdf_pages(page.pdf)} ({len(page.pdf) / 1024:.0f} kB)")
    if "--screenshot" in argv:
        Path(argv[argv.index("--screenshot") + 1]).write_bytes(page.screenshot_png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
