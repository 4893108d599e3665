"""The HTML animation's player in a real browser (Chromium through Playwright): it draws the
scene on its canvas, the frames change as it plays, the slider shows a chosen frame, and no
script error is raised."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

import lagrangian as lg

#: The canvas as a list of its pixels' red values, and how many are not white.
PIXELS = """() => {
  const canvas = document.querySelector("canvas");
  const data = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  let ink = 0, sum = 0;
  for (let i = 0; i < data.length; i += 4) {
    if (data[i] < 240 || data[i + 1] < 240 || data[i + 2] < 240) { ink += 1; sum += i; }
  }
  return [ink, sum];
}"""

pytestmark = pytest.mark.slow


@pytest.mark.parametrize("name", ["double_pendulum", "two_mesh_circuit", "heavy_symmetric_top"])
def test_the_player_draws_and_plays_the_scene(browser: Any, tmp_path: Path, name: str) -> None:
    system = lg.examples.get(name)()
    trajectory = lg.simulate(system, t_span=float(system.simulation["t_end"]) / 4, samples=200)
    page_file = tmp_path / f"{name}.html"
    lg.render.animate(system, trajectory, page_file, frames=40, fps=20)
    page = browser.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(page_file.as_uri())
    page.wait_for_timeout(300)
    first = page.evaluate(PIXELS)
    page.wait_for_timeout(700)  # about 14 frames at 20 per second
    later = page.evaluate(PIXELS)
    page.fill("input[type=range]", "0")
    page.dispatch_event("input[type=range]", "input")
    again = page.evaluate(PIXELS)
    page.close()
    assert not errors
    assert first[0] > 500 and later[0] > 500  # the scene is drawn
    assert later != first  # it moves
    assert page_file.stat().st_size < 100_000
    assert again[0] > 500 and page_file.read_text().count("<canvas") == 1
