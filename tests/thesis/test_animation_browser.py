"""``obturator simulate --animate`` in a real browser: the slider moves the ball.

Headless Chromium (Debian's ``chromium``; ``.ci/run`` installs it) opens the standalone
animation alone in an empty folder, driven through the DevTools protocol (the client
of ``test_explorer_browser``); the test drags nothing it cannot see: it clicks the
slider's rail at three quarters of its length with synthetic mouse events and checks
that the slider, the ball's surface, the theta(t) marker and its drawn label moved to a
later frame. In CI a missing browser fails the test instead of skipping it.
"""

from __future__ import annotations

import re

import pytest
from test_explorer_browser import DevTools

from obturator.cli import main

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def animation_page(tmp_path_factory):
    out = tmp_path_factory.mktemp("animation") / "opening.html"
    argv = ["simulate", "--case", "spin-rig", "--spin-rate", "300", "--no-check"]
    assert main([*argv, "--animate", str(out)]) == 0
    return out


def test_animation_is_standalone(animation_page):
    text = animation_page.read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]*\ssrc=", text)  # plotly.js inline: works offline
    markup = re.sub(r"<script[^>]*>.*?</script>", "", text, flags=re.DOTALL)
    assert not re.search(r'(?:src|href)="(?!data:|#)', markup)


def test_slider_changes_the_frame(animation_page, chromium):
    tools = DevTools(chromium, width=1300, height=800)
    fig = "document.getElementById('opening-animation')"
    try:
        tools.page("Page.enable")
        tools.page("Page.navigate", url=animation_page.as_uri())
        tools.wait_for(f"!!({fig} && {fig}.querySelector('.slider-rail-rect'))")
        tools.wait_for(f"!!({fig}._fullData && {fig}._fullData.length > 0)")
        # what frame 0 shows: the ball's surface (its x, as plotly.js holds it), the theta(t)
        # marker and its drawn label
        state = (
            f"(() => [{fig}.layout.sliders[0].active, JSON.stringify({fig}.data[0].x),"
            f" {fig}.data[{fig}.data.length - 1].x[0],"
            f" [...{fig}.querySelectorAll('.scatterlayer .textpoint text')].pop().textContent])()"
        )
        before = tools.js(state)
        assert before[0] == 0 and before[2] == 0.0
        assert "t = 0 s" in before[3]
        rail = tools.js(
            f"(() => {{ const r = {fig}.querySelector('.slider-rail-rect')"
            ".getBoundingClientRect(); return [r.x, r.y, r.width, r.height]; })()"
        )
        x, y = rail[0] + 0.75 * rail[2], rail[1] + rail[3] / 2
        tools.click(x, y)
        after = tools.wait_for(
            f"(() => {{ const s = {state}; return s[0] > 0 && s[2] > 0 && s; }})()",
            timeout=20,
        )
        n = tools.js(f"{fig}.layout.sliders[0].steps.length")
        assert 0.6 * n < after[0] < 0.9 * n  # about three quarters along
        assert after[1] != before[1]  # the ball turned
        t_frame = float(tools.js(f"{fig}.layout.sliders[0].steps[{after[0]}].label"))
        assert after[2] == pytest.approx(t_frame, rel=1e-2)  # the marker is at that time
        shown = re.search(r"t = ([\d.e+-]+) s, theta", after[3])  # the marker's label
        assert shown and float(shown.group(1)) == pytest.approx(t_frame, rel=1e-2)
    finally:
        tools.close()
