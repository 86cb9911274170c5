"""The reproduce report in a real browser: one self-contained HTML file that renders.

Chromium (Debian's ``chromium`` package, installed by ``.ci/run``) loads a copy of
``report.html`` alone in an empty folder, headless; the test checks that every
embedded figure decodes, that the interactive explorer's Plotly figures were
drawn (their SVG roots exist in the DOM after scripts ran), and that a screenshot
is not blank. In CI a missing browser fails the test instead of skipping it.
"""

from __future__ import annotations

import base64
import io
import re
import shutil
import subprocess

import matplotlib.image as mpimg
import numpy as np
import pytest

from obturator.cli import main


def _chromium(browser: str, *args: str) -> subprocess.CompletedProcess:
    cmd = [
        browser,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--hide-scrollbars",
        "--virtual-time-budget=20000",
        *args,
    ]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=180, check=False)


# the module's fixture runs a quick reproduce (~20 s)
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def lone_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("reproduce")
    assert main(["reproduce", "--out", str(out), "--quick", "--no-progress"]) == 0
    lone = tmp_path_factory.mktemp("lone") / "report.html"
    shutil.copy(out / "report.html", lone)  # nothing else travels with it
    return lone


def test_report_is_self_contained(lone_report):
    text = lone_report.read_text(encoding="utf-8")
    sources = re.findall(r'<img[^>]*\ssrc="([^"]+)"', text)
    assert len(sources) == 22  # 21 thesis figures and the validation figure
    assert all(s.startswith("data:image/png;base64,") for s in sources)
    for s in sources:  # every figure decodes to a real image
        img = mpimg.imread(io.BytesIO(base64.b64decode(s.split(",", 1)[1])), format="png")
        assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100
        assert float(np.std(img)) > 0.01  # not a blank canvas
    # no link to anything the reader does not have (plotly.js itself is inline)
    markup = re.sub(r"<script[^>]*>.*?</script>", "", text, flags=re.DOTALL)
    assert not re.search(r'(?:src|href)="(?!data:|#)', markup)
    assert not re.search(r"<script[^>]*\ssrc=", text)
    # cite the thesis, not our working notes (in the text: base64 image data may spell
    # "SPEC" by chance, about once per 7 MB)
    assert "SPEC" not in re.sub(r'data:[^"]*', "", markup)


def test_report_renders_in_chromium(lone_report, tmp_path, chromium):
    browser = chromium
    dom = _chromium(browser, "--dump-dom", lone_report.as_uri())
    assert dom.returncode == 0, dom.stderr[-2000:]
    html = dom.stdout
    # the two explorer figures were drawn by plotly.js (SVG roots exist only after it ran)
    # and the animations of the selected runs (obturator.animation), drawn by the same
    # inline plotly.js
    for div in ("tcr-explorer", "theta-explorer", "opening-150", "opening-400"):
        assert f'id="{div}"' in html
    assert html.count('class="main-svg"') >= 8
    assert "measured runs" in html  # the trace of the 54 runs made it into the plot
    shot = tmp_path / "shot.png"
    res = _chromium(
        browser, "--window-size=1280,1600", f"--screenshot={shot}", lone_report.as_uri()
    )
    assert res.returncode == 0 and shot.is_file(), res.stderr[-2000:]
    img = mpimg.imread(shot)
    assert float(np.std(img[..., :3])) > 0.05  # text, tables and figures, not a blank page
