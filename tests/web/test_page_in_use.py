"""The page as a student and a teacher use it, in headless Chromium at a desktop's and a phone's
size: the server outlives the command line's time limit and the page says when it is gone;
no panel shows a model other than the one in the editor; every equation of every built-in
example fits its box; the keyboard reaches every control; sliders are exact and kept in the
link; the animation pauses and steps; the plot's legend is readable.  Screenshots go to
tests/web/artifacts/."""

from __future__ import annotations

import functools
import json
import os
import signal
import subprocess
import sys
import time
from typing import Any

import pytest
from playground_setup import free_port
from test_browser import ARTIFACTS

from lagrangian import examples
from lagrangian.web.runs import run

pytestmark = pytest.mark.slow

SIZES = {"desktop": {"width": 1366, "height": 768}, "phone": {"width": 390, "height": 844}}


def _open(browser: Any, url: str, size: str = "desktop") -> Any:
    context = browser.new_context(viewport=SIZES[size], accept_downloads=True)
    page = context.new_page()
    page.goto(url)
    page.wait_for_selector("body[data-ready=true]", timeout=120_000)
    return page


def _shot(page: Any, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / name), full_page=True)


def _settled(page: Any) -> None:
    """Wait until the page shows results for the text in its editor (nothing out of date)."""
    page.wait_for_function(
        """() => {
          const v = document.body.dataset.version;
          return ["equations", "simulation-panel"].every(
            (id) => document.getElementById(id).dataset.version === v) &&
            !document.querySelector(".panel.stale");
        }""",
        timeout=120_000,
    )


def test_the_server_outlives_a_3_s_limit_and_the_page_says_when_it_is_gone(
    browser: Any,
) -> None:
    port = free_port()
    started = time.monotonic()
    server = subprocess.Popen(
        [sys.executable, "-m", "lagrangian", "serve", "--no-browser", "--port", str(port)],
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "LAGRANGIAN_TIME_LIMIT": "3"},
    )
    try:
        assert server.stderr is not None
        assert "the playground is at" in server.stderr.readline()
        page = _open(browser, f"http://127.0.0.1:{port}/")
        time.sleep(max(0.0, started + 10 - time.monotonic()))
        assert server.poll() is None, "the server stopped"
        page.select_option("[data-testid=examples]", "simple_pendulum")
        page.wait_for_function("() => document.getElementById('editor').value.includes('imple')")
        _settled(page)
        assert page.locator("[data-testid=connection]").is_hidden()
    finally:
        server.send_signal(signal.SIGINT)
        server.communicate(timeout=60)
    banner = page.wait_for_selector("[data-testid=connection]", state="visible", timeout=30_000)
    assert "does not answer" in banner.inner_text()
    page.select_option("[data-testid=examples]", "double_pendulum")  # no silent failure
    page.wait_for_timeout(500)
    assert page.locator("[data-testid=connection]").is_visible()
    assert "done" not in page.inner_text("[data-testid=status]")
    _shot(page, "server_gone.png")
    page.context.close()


@pytest.mark.parametrize("size", list(SIZES))
def test_no_panel_shows_another_model(browser: Any, page_server: str, size: str) -> None:
    page = _open(browser, page_server + "/", size)
    menu = page.locator("[data-testid=examples]")
    menu.focus()
    for _ in range(4):  # arrowing through the menu: each step picks an example
        page.keyboard.press("ArrowDown")
        page.wait_for_timeout(150)
    _settled(page)
    chosen = page.input_value("[data-testid=examples]")
    assert page.input_value("[data-testid=editor]") == examples.model_text(chosen)
    derived = json.loads(run("derive", examples.model_text(chosen), "yaml", {})[1])
    sliders = page.eval_on_selector_all(
        "#sliders input[type=number]", "(els) => els.map((e) => e.dataset.name)"
    )
    assert set(derived["parameters"]) <= set(sliders)
    # an edit: the old results are marked at once, the downloads wait for the new ones
    page.click("[data-testid=editor]")
    page.keyboard.press("Control+End")
    page.keyboard.type("\n# an edit\n")
    assert page.locator(".panel.stale").count() >= 2
    assert page.get_attribute("[data-testid=download-csv]", "aria-disabled") == "true"
    _shot(page, f"stale_{size}.png")
    _settled(page)
    with page.expect_download() as caught:
        page.click("[data-testid=download-csv]")
    with open(caught.value.path(), encoding="utf-8") as saved:
        rows = saved.read().splitlines()
    header = rows[0].split(",")
    assert header[0] == "t" and set(derived["coordinates"]) <= set(header)
    samples = page.inner_text("[data-testid=summary]").split()[0]
    assert len(rows) - 1 == int(samples)
    _shot(page, f"current_{size}.png")
    page.context.close()


#: Each typeset row's measures: [its start, the width of its widest formula (the KaTeX box
#: itself, not the display around it), the width of its box, whether the box scrolls sideways,
#: the smallest type in it (px), the page's text size (px)].  A row too large to typeset at
#: once waits for its button ("Show this equation"), which must itself fit.
ROW_MEASURES = """() => [...document.querySelectorAll('#equations .item')].map((item) => {
    if (item.querySelector('.show-large')) {
      return ['(' + item.dataset.latex.length + ' characters, typeset when asked)',
        item.scrollWidth, item.clientWidth, item.scrollWidth > item.clientWidth, 99, 0];
    }
    if (!item.dataset.typeset) renderRow(item);
    const box = item.getBoundingClientRect().left + item.clientLeft;
    let widest = 0;
    for (const formula of item.querySelectorAll('.katex-html')) {
      const range = document.createRange();
      range.selectNodeContents(formula);
      widest = Math.max(widest, range.getBoundingClientRect().right - box);
    }
    const type = [...item.querySelectorAll('.katex')].map(
      (k) => parseFloat(getComputedStyle(k).fontSize));
    return [item.dataset.latex.slice(0, 40), Math.ceil(widest), item.clientWidth,
      item.scrollWidth > item.clientWidth || item.classList.contains('wide'),
      Math.min(...type), parseFloat(getComputedStyle(document.body).fontSize)];
  })"""


def _misfits(page: Any, panel: str = "equations") -> list[str]:
    """The rows of the ``panel`` (the equations, or the analysis) wider than their box,
    scrolling sideways, or set in a type smaller than the page's text."""
    return [
        f"{start}… {width}/{box} px{' scrolls' if scrolls else ''}, type {type_px:.1f} px"
        for start, width, box, scrolls, type_px, text_px in page.evaluate(
            ROW_MEASURES.replace("#equations", f"#{panel}")
        )
        if width > box or scrolls or type_px < text_px - 0.05
    ]


@functools.cache
def _analysis_latex(name: str) -> str:
    """The analysis of an example as the page receives it (computed once for both sizes)."""
    status, body = run("analyze", examples.model_text(name), "yaml", {})
    assert status == 200, name
    return str(json.loads(body)["latex"])


@pytest.mark.parametrize("size", list(SIZES))
def test_every_analysis_of_every_example_fits_its_box(
    browser: Any, page_server: str, size: str
) -> None:
    """The analysis panel's rows (momenta, energy, equilibria, modes...) of every example in
    the menu fit their box as the derivation's do."""
    page = _open(browser, page_server + "/", size)
    listed = page.eval_on_selector_all(
        "[data-testid=examples] option", "(os) => os.map((o) => o.value).filter(Boolean)"
    )
    misfits: dict[str, list[str]] = {}
    for name in listed:
        latex = _analysis_latex(name)
        page.evaluate("(latex) => typeset(document.getElementById('analysis'), latex, -1)", latex)
        if misfit := _misfits(page, "analysis"):
            misfits[name] = misfit
        if name in PICTURED:
            page.locator("#analysis").screenshot(
                path=str(ARTIFACTS / f"analysis_{name}_{size}.png")
            )
    page.context.close()
    assert not misfits, json.dumps(misfits, indent=1)


#: Examples whose equations are kept as pictures: short rows, matrices whose entries are named
#: and listed, a matrix equation written row by row on a phone, the Whipple bicycle.
PICTURED = ("double_pendulum", "asymmetric_body", "physical_pendulum_3d", "rolling_coin")


@pytest.mark.parametrize("size", list(SIZES))
def test_every_equation_of_every_example_fits_its_box(
    browser: Any, page_server: str, size: str
) -> None:
    page = _open(browser, page_server + "/", size)
    listed = page.eval_on_selector_all(
        "[data-testid=examples] option", "(os) => os.map((o) => o.value).filter(Boolean)"
    )
    assert "whipple_bicycle" in listed and "hard_disk_gas" in listed  # built in Python too
    assert sorted(listed) == sorted([*examples.names(), *examples.BENCHMARKS])
    misfits: dict[str, list[str]] = {}
    ARTIFACTS.mkdir(exist_ok=True)
    for name in listed:
        status, body = run("derive", examples.model_text(name), "yaml", {})
        assert status == 200, name
        latex = json.loads(body)["latex"]
        page.evaluate("(latex) => typeset(document.getElementById('equations'), latex, -1)", latex)
        if misfit := _misfits(page):
            misfits[name] = misfit
        if name in PICTURED:
            page.locator("#equations").screenshot(
                path=str(ARTIFACTS / f"equations_{name}_{size}.png")
            )
    # the bicycle's rows too large to typeset at once: the smallest, shown, fits as well
    show = page.locator("#equations .show-large").all()
    assert show, "the Whipple bicycle's largest rows wait to be asked for"
    sizes = [len(button.evaluate("(b) => b.parentElement.dataset.latex")) for button in show]
    smallest = show[sizes.index(min(sizes))]
    item = smallest.evaluate_handle("(button) => button.parentElement")
    smallest.click()
    page.wait_for_function("(item) => item.dataset.typeset === 'true'", arg=item)
    item.scroll_into_view_if_needed()
    page.screenshot(path=str(ARTIFACTS / f"equations_whipple_bicycle_shown_{size}.png"))
    if misfit := _misfits(page):
        misfits["whipple_bicycle"] = misfit
    page.context.close()
    assert not misfits, json.dumps(misfits, indent=1)


def test_equations_are_set_again_when_the_window_narrows(browser: Any, page_server: str) -> None:
    """Rows set for a desktop's width are set again for a phone's when the window narrows
    (a phone turned, a window resized): none is left wider than its new box."""
    page = _open(browser, page_server + "/")
    status, body = run("derive", examples.model_text("asymmetric_body"), "yaml", {})
    assert status == 200
    latex = json.loads(body)["latex"]
    page.evaluate("(latex) => typeset(document.getElementById('equations'), latex, -1)", latex)
    page.evaluate("() => document.querySelectorAll('#equations .item').forEach(renderRow)")
    assert not _misfits(page)
    wide = page.evaluate("() => document.querySelector('#equations .item:last-child').clientWidth")
    page.set_viewport_size(SIZES["phone"])
    page.wait_for_function(
        "(wide) => document.querySelector('#equations .item:last-child').clientWidth < wide",
        arg=wide,
    )
    # a resize is reported before the next frame is drawn
    page.evaluate(
        "() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))"
    )
    assert not _misfits(page)
    page.context.close()


#: What a control is called to a screen reader: its label, aria-label or text.
ACCESSIBLE_NAME = """(el) => (el.labels && el.labels.length ? el.labels[0].innerText : '') ||
  el.getAttribute('aria-label') || el.innerText || ''"""
FOCUS_SHOWN = """(el) => {
  const shown = (node) => { const s = getComputedStyle(node);
    return s.outlineStyle !== 'none' && parseFloat(s.outlineWidth) >= 2; };
  return shown(el) || (el.id === 'editor' && shown(el.closest('.editor')));
}"""
CONTROLS = "button:not([hidden]), select, input, textarea, a[href]"


@pytest.mark.parametrize("size", list(SIZES))
def test_a_keyboard_reaches_every_control(browser: Any, page_server: str, size: str) -> None:
    page = _open(browser, page_server + "/", size)
    _settled(page)
    expected = page.eval_on_selector_all(
        CONTROLS,
        "(els) => els.filter((e) => e.offsetParent !== null).map((e) => e.id || e.dataset.name "
        "+ ':' + e.type + ':' + e.className)",
    )
    reached: list[str] = []
    page.focus("[data-testid=examples]")
    text = page.input_value("[data-testid=editor]")
    for _ in range(3 * len(expected) + 20):
        focused = page.evaluate_handle("document.activeElement")
        key = page.evaluate(
            "(e) => e.id || e.dataset.name + ':' + e.type + ':' + e.className", focused
        )
        if key not in reached and key != "undefined:undefined:":  # past the last: the page
            reached.append(key)
            assert page.evaluate(ACCESSIBLE_NAME, focused).strip(), key
            assert page.evaluate(FOCUS_SHOWN, focused), f"no visible focus on {key}"
        if key == "editor" and "editor-walk" not in reached:
            reached.append("editor-walk")
            _shot(page, f"editor_focus_{size}.png")
        page.keyboard.press("Tab")
    assert page.input_value("[data-testid=editor]") == text  # Tab left the editor untouched
    assert set(expected) <= set(reached), set(expected) - set(reached)
    # Escape (or Ctrl+]) then Tab indents, as code editors do
    page.focus("[data-testid=editor]")
    page.evaluate("document.getElementById('editor').setSelectionRange(0, 0)")
    page.keyboard.press("Escape")
    page.keyboard.press("Tab")
    assert page.input_value("[data-testid=editor]").startswith("  ")
    page.keyboard.press("Shift+Tab")
    assert page.input_value("[data-testid=editor]") == text
    page.context.close()


def _contrast(color: str) -> float:
    """WCAG contrast ratio of an ``rgb(r, g, b)`` colour on white."""
    channels = [int(c) / 255 for c in color[color.index("(") + 1 : -1].split(",")[:3]]
    linear = [c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in channels]
    luminance = 0.2126 * linear[0] + 0.7152 * linear[1] + 0.0722 * linear[2]
    return 1.05 / (luminance + 0.05)


def test_sliders_are_exact_signed_reset_and_kept_in_the_link(
    browser: Any, page_server: str
) -> None:
    page = _open(browser, page_server + "/")
    page.select_option("[data-testid=examples]", "simple_pendulum")
    page.wait_for_selector("#sliders input[type=number][data-name=g]", timeout=60_000)
    _settled(page)
    assert float(page.get_attribute("#sliders input[type=range][data-name=theta]", "min")) < 0
    assert float(page.get_attribute("#sliders input[type=range][data-name=theta_dot]", "min")) < 0

    def asked(response: Any) -> bool:
        return response.url.endswith("/api/simulate") and "theta=-0.3" in (
            response.request.post_data or ""
        )

    with page.expect_response(asked) as answer:
        page.fill("#sliders input[type=number][data-name=g]", "9.8")
        page.fill("#sliders input[type=number][data-name=theta]", "-0.3")
    request = json.loads(answer.value.request.post_data)
    assert {"g=9.8", "theta=-0.3"} <= set(request["options"]["set"])  # exact, as typed
    assert answer.value.json()["summary"]["parameters"]["g"] == 9.8
    page.wait_for_function("() => location.hash.includes('theta%3D-0.3')")
    link = page.url
    other = _open(browser, link)
    _settled(other)
    assert other.input_value("#sliders input[type=number][data-name=theta]") == "-0.3"
    column = other.evaluate("state.run.answer.columns.theta[0]")
    assert column == pytest.approx(-0.3)
    other.click("#sliders .reset[aria-label^='reset theta ']")
    assert other.input_value("#sliders input[type=number][data-name=theta]") != "-0.3"
    other.wait_for_function("() => !location.hash.includes('theta%3D')")
    other.context.close()
    page.context.close()


def test_the_animation_pauses_steps_and_runs_at_the_motions_pace(
    browser: Any, page_server: str
) -> None:
    page = _open(browser, page_server + "/")
    page.select_option("[data-testid=examples]", "series_rlc")
    page.wait_for_function("() => document.getElementById('editor').value.includes('RLC')")
    _settled(page)
    t = page.evaluate("state.run.answer.columns.t")
    rate = page.evaluate("state.rate")
    assert rate < (t[-1] - t[0]) / 3  # the whole run lasts seconds on screen, not a flicker
    page.click("[data-testid=play]")  # pause
    shown = page.input_value("[data-testid=time]")
    page.wait_for_timeout(400)
    assert page.input_value("[data-testid=time]") == shown
    page.click("[data-testid=step-forward]")
    page.wait_for_timeout(100)
    assert int(page.input_value("[data-testid=time]")) == int(shown) + 1
    legend = page.eval_on_selector_all(
        "[data-testid=legend] li", "(els) => els.map((e) => getComputedStyle(e).color)"
    )
    assert legend and all(_contrast(color) >= 4.5 for color in legend), legend
    _shot(page, "animation_paused.png")
    page.context.close()
