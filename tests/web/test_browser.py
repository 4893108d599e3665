"""The page in a real browser (headless Chromium from the system's packages, driven by
Playwright): an example is typeset with KaTeX and animated on the canvas, a slider re-runs
the simulation, an error is listed at its line, the URL keeps the model.  Screenshots go to
tests/web/artifacts/ (and, with LAGRANGIAN_README_SCREENSHOT=1, to docs/playground.png)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

ARTIFACTS = Path(__file__).resolve().parent / "artifacts"
README_PICTURE = Path(__file__).resolve().parents[2] / "docs" / "playground.png"
BROKEN = "coordinates: [x]\nparameters: {k: 1}\npotential: k*x**\nkinetic: x_dot**2/2\n"
#: How many pixels of a canvas are not its white background.
INK = """(id) => {
  const canvas = document.getElementById(id);
  const data = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  let ink = 0;
  for (let i = 0; i < data.length; i += 4) {
    if (data[i] < 240 || data[i + 1] < 240 || data[i + 2] < 240) ink += 1;
  }
  return ink;
}"""

pytestmark = pytest.mark.slow


@pytest.fixture
def page(browser: Any, page_server: str) -> Iterator[Any]:
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    opened = context.new_page()
    failures: list[str] = []
    opened.on("requestfailed", lambda request: failures.append(request.url))
    opened.goto(page_server + "/")
    opened.wait_for_selector("body[data-ready=true]", timeout=90_000)
    yield opened
    context.close()
    assert not failures, failures


def _shot(page: Any, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / name), full_page=True)


def test_an_example_is_typeset_and_animated(page: Any) -> None:
    assert "double pendulum" in page.input_value("[data-testid=editor]").lower()
    assert page.locator("[data-testid=equations] .katex").count() >= 2  # steps, matrix form
    assert page.locator("[data-testid=equations] .katex-error").count() == 0
    page.wait_for_timeout(500)  # a few frames of the animation
    assert page.evaluate(INK, "canvas") > 500
    assert page.evaluate(INK, "plot") > 500
    page.click("[data-testid=analyze-button]")
    page.wait_for_selector("[data-testid=analysis] .item", timeout=90_000)
    page.locator("[data-testid=analysis]").scroll_into_view_if_needed()  # typeset in view
    page.wait_for_selector("[data-testid=analysis] .katex", timeout=90_000)
    _shot(page, "double_pendulum.png")
    if os.environ.get("LAGRANGIAN_README_SCREENSHOT"):
        page.screenshot(path=str(README_PICTURE))


def test_a_slider_reruns_the_simulation(page: Any) -> None:
    page.select_option("[data-testid=examples]", "simple_pendulum")
    page.wait_for_selector("#sliders input[type=range][data-name=l]", timeout=60_000)
    assert "simple" in page.input_value("[data-testid=editor]").lower()
    with page.expect_response(lambda r: r.url.endswith("/api/simulate")) as answer:
        page.eval_on_selector(
            "#sliders input[type=range][data-name=l]",
            "(el) => { el.value = 2.5; el.dispatchEvent(new Event('input')); }",
        )
    response = answer.value
    chosen = float(page.input_value("#sliders input[type=number][data-name=l]"))
    assert response.status == 200 and chosen == 2.5  # exact: no snapping to the slider's steps
    assert f"l={chosen:g}" in response.request.post_data
    assert response.json()["summary"]["parameters"]["l"] == pytest.approx(chosen)
    page.wait_for_timeout(300)
    assert page.evaluate(INK, "canvas") > 200
    _shot(page, "slider.png")


def test_an_error_is_listed_at_its_line(page: Any) -> None:
    page.fill("[data-testid=editor]", BROKEN)
    item = page.wait_for_selector("[data-testid=errors] li", timeout=60_000)
    assert "line 3" in item.inner_text() and "potential" in item.inner_text()
    assert page.inner_text("#gutter .bad") == "3"
    _shot(page, "error.png")


def test_the_url_keeps_the_model(page: Any, browser: Any) -> None:
    model = "coordinates: [x]\nkinetic: x_dot**2/2\npotential: x**4/4\n"
    page.fill("[data-testid=editor]", model)
    page.wait_for_function("location.hash.includes('model=')")
    link = page.url
    other = browser.new_page()
    other.goto(link)
    other.wait_for_selector("body[data-ready=true]", timeout=90_000)
    assert other.input_value("[data-testid=editor]") == model
    assert other.locator("[data-testid=equations] .katex").count() >= 1
    other.close()


def test_the_generated_code_downloads(page: Any) -> None:
    import lagrangian as lg
    from lagrangian import examples
    from lagrangian.numerics.export import export

    downloads: list[Any] = []
    page.on("download", lambda download: downloads.append(download))
    page.select_option("[data-testid=export-language]", "c")
    page.click("[data-testid=download-code]")
    for _ in range(300):
        if len(downloads) == 2:
            break
        page.wait_for_timeout(100)
    expected = export(lg.loads(examples.model_text("double_pendulum")), "c")
    got = {d.suggested_filename: Path(d.path()).read_text(encoding="utf-8") for d in downloads}
    assert got == expected


def test_the_plot_shows_a_phase_portrait_and_the_energy(page: Any) -> None:
    kinds = page.eval_on_selector_all(
        "[data-testid=plot-kind] option", "(os) => os.map(o => o.value)"
    )
    assert kinds == ["coordinates", "phase:theta", "phase:phi", "energy"]
    before = page.evaluate("() => document.getElementById('plot').toDataURL()")
    page.select_option("[data-testid=plot-kind]", "phase:phi")
    page.wait_for_timeout(200)
    assert page.evaluate(INK, "plot") > 500
    assert page.evaluate("() => document.getElementById('plot').toDataURL()") != before
    page.select_option("[data-testid=plot-kind]", "energy")
    page.wait_for_timeout(200)
    assert page.evaluate(INK, "plot") > 300
    _shot(page, "phase_and_energy.png")
