"""The playground's canvas draws the run's scene (the one the command line's animations draw)
at the frame its time slider shows, in headless Chromium at a desktop's and a phone's size:
a rolling disc, a top with its axes, a circuit with its mesh currents, a pendulum, one after
the other (each drawing belongs to the model then in the editor), and an impact's flash.

The pixels are read back where the scene's format puts a body at that frame (its panel's
square, title band and margin, computed here from the format, not by the page's script); the
pendulum's bob where its closed form puts it, (l sin theta, -l cos theta) at the slider's
sample.  Screenshots go to tests/web/artifacts/."""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from test_browser import ARTIFACTS

from lagrangian import examples
from lagrangian.web.runs import run

pytestmark = pytest.mark.slow

SIZES = {"desktop": {"width": 1366, "height": 768}, "phone": {"width": 390, "height": 844}}
#: The format's panel: a title band, a margin, widths in pixels of a 400-pixel panel.
TITLE, MARGIN, REFERENCE = 22, 10, 400
#: The examples drawn one after the other, and the share of the run their slider is set to.
SHOWN = {"rolling_disc": 0.6, "heavy_symmetric_top": 0.45, "two_mesh_circuit": 0.3,
         "simple_pendulum": 0.8}  # fmt: skip

#: The canvas's pixels in a square of side 2 r + 1 about (u, v): [[r, g, b], ...].
PIXELS = """([u, v, r]) => {
  const canvas = document.getElementById("canvas");
  const data = canvas.getContext("2d").getImageData(u - r, v - r, 2 * r + 1, 2 * r + 1).data;
  const out = [];
  for (let i = 0; i < data.length; i += 4) out.push([data[i], data[i + 1], data[i + 2]]);
  return out;
}"""
DRAWN = """(k) => state.drawn && state.drawn.frame === k &&
  state.drawn.version === Number(document.body.dataset.version) &&
  state.run.version === state.drawn.version"""


def boxes(count: int, width: float, height: float) -> list[tuple[float, float, float]]:
    """Each panel's square (x, y, side): one size, in the grid that makes it largest, the grid
    centred on the canvas."""
    best = (0.0, 1, 1)
    for columns in range(1, count + 1):
        rows = math.ceil(count / columns)
        side = min(width / columns, height / rows)
        if side > best[0]:
            best = (side, columns, rows)
    side, columns, rows = best
    left, top = (width - columns * side) / 2, (height - rows * side) / 2
    return [(left + (p % columns) * side, top + (p // columns) * side, side) for p in range(count)]


def to_pixels(panel: dict[str, Any], box: tuple[float, float, float], points: Any) -> np.ndarray:
    """A panel's points (..., 2) on the canvas: the bounds fill the square under the title
    band, one scale on both axes when the panel is ``equal``, y up."""
    x0, x1, y0, y1 = panel["bounds"]
    bx, by, side = box
    w, h = side - 2 * MARGIN, side - TITLE - 2 * MARGIN
    sx, sy = w / ((x1 - x0) or 1), h / ((y1 - y0) or 1)
    if panel["equal"]:
        sx = sy = min(sx, sy)
    ox = bx + MARGIN + (w - sx * (x1 - x0)) / 2
    oy = by + TITLE + MARGIN + (h - sy * (y1 - y0)) / 2
    p = np.asarray(points, dtype=float)
    return np.stack([ox + (p[..., 0] - x0) * sx, oy + (y1 - p[..., 1]) * sy], axis=-1)


def shape_points(shape: dict[str, Any], k: int) -> np.ndarray:
    """A shape's points at frame k, (N, 2)."""
    key = {"line": "points", "dot": "at", "circle": "centre", "text": "at"}[shape["type"]]
    value = shape[key][k] if key in shape["moving"] else shape[key]
    return np.asarray(value, dtype=float).reshape(-1, 2)


def segment_distance(point: np.ndarray, polyline: np.ndarray) -> float:
    """The distance from ``point`` to a polyline (a single point when it has one)."""
    if len(polyline) == 1:
        return float(np.linalg.norm(point - polyline[0]))
    a, b = polyline[:-1], polyline[1:]
    ab = b - a
    share = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.maximum((ab**2).sum(1), 1e-12), 0, 1)
    return float(np.min(np.linalg.norm(a + share[:, None] * ab - point, axis=1)))


def visible_point(panel: dict[str, Any], box: Any, element: int, shape: int, k: int) -> Any:
    """The pixel of shape ``shape`` of element ``element`` at frame k that lies farthest from
    everything drawn after it (so nothing covers it), and that distance."""
    drawn = [s for e in panel["elements"] for s in e["shapes"]]
    index = sum(len(e["shapes"]) for e in panel["elements"][:element]) + shape
    own = to_pixels(panel, box, shape_points(drawn[index], k))
    lengths = np.zeros(len(own))
    if drawn[index]["type"] == "line":  # the middles of its segments, the longest first
        lengths = np.linalg.norm(own[1:] - own[:-1], axis=1)
        own = (own[1:] + own[:-1]) / 2
    later = [to_pixels(panel, box, shape_points(s, k)) for s in drawn[index + 1 :]]
    clearance = [min((segment_distance(p, other) for other in later), default=99.0) for p in own]
    best = max(range(len(own)), key=lambda i: (min(clearance[i], 8.0), lengths[i]))
    return own[best], clearance[best]


def ink_of(pixels: list[list[int]], color: str) -> float:
    """How much of ``color`` the best pixel holds over white (1: the colour itself), among
    pixels that are that colour blended with white (each channel within 30 of the blend)."""
    target = np.array([int(color[i : i + 2], 16) for i in (1, 3, 5)], dtype=float)
    best = 0.0
    for pixel in np.asarray(pixels, dtype=float):
        span = 255.0 - target
        share = float(np.clip(((255.0 - pixel) @ span) / max(span @ span, 1e-9), 0, 1))
        if np.max(np.abs(255.0 - share * span - pixel)) <= 30:
            best = max(best, share)
    return best


def open_page(browser: Any, url: str, size: str) -> tuple[Any, list[str]]:
    """The page at ``size``, ready, and the list its script errors go to."""
    context = browser.new_context(viewport=SIZES[size])
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(url)
    page.wait_for_selector("body[data-ready=true]", timeout=120_000)
    return page, errors


def settled(page: Any, name: str) -> None:
    """The example's text in the editor and its run shown (nothing out of date)."""
    text = examples.model_text(name)
    page.wait_for_function("(text) => document.getElementById('editor').value === text", arg=text,
                           timeout=60_000)  # fmt: skip
    page.wait_for_function(
        """() => document.getElementById('simulation-panel').dataset.version ===
                 document.body.dataset.version && !document.querySelector('.panel.stale')""",
        timeout=120_000,
    )


def show_frame(page: Any, k: int) -> dict[str, Any]:
    """Pause, set the time slider to frame k, and return what the page drew."""
    if page.evaluate("state.playing"):
        page.click("[data-testid=play]")
    chosen = "(el, k) => { el.value = k; el.dispatchEvent(new Event('input')); }"
    page.eval_on_selector("[data-testid=time]", chosen, k)
    page.wait_for_function(DRAWN, arg=k, timeout=10_000)
    drawn: dict[str, Any] = page.evaluate("state.drawn")
    return drawn


def check_shape(page: Any, scene: dict[str, Any], size: list[int], at: tuple[int, int, int],
                k: int) -> None:  # fmt: skip
    """Shape ``at`` = (panel, element, shape) is drawn in its colour where the format puts it."""
    p, e, s = at
    panel = scene["panels"][p]
    box = boxes(len(scene["panels"]), *size)[p]
    point, clearance = visible_point(panel, box, e, s, k)
    assert clearance >= 2.5, (panel["elements"][e]["kind"], clearance)  # not under another
    shape = panel["elements"][e]["shapes"][s]
    u, v = (round(float(c)) for c in point)
    pixels = page.evaluate(PIXELS, [u, v, 1])
    share = ink_of(pixels, shape["color"])
    assert share >= 0.35, (panel["elements"][e]["kind"], shape["color"], (u, v), pixels)


def first(scene: dict[str, Any], kind: str, shape_type: str) -> tuple[int, int, int]:
    """(panel, element, shape) of the first shape of ``shape_type`` of an element of ``kind``."""
    for p, panel in enumerate(scene["panels"]):
        for e, element in enumerate(panel["elements"]):
            for s, shape in enumerate(element["shapes"]):
                if element["kind"] == kind and shape["type"] == shape_type:
                    return p, e, s
    raise AssertionError(f"no {shape_type} of a {kind}")


@pytest.mark.parametrize("size", list(SIZES))
def test_the_canvas_draws_the_scene_at_the_sliders_frame(
    browser: Any, page_server: str, size: str
) -> None:
    page, errors = open_page(browser, page_server + "/", size)
    ARTIFACTS.mkdir(exist_ok=True)
    for name, share in SHOWN.items():
        page.select_option("[data-testid=examples]", name)
        settled(page, name)
        status, body = run("simulate", examples.model_text(name), "yaml", {})
        assert status == 200
        document = json.loads(body)
        scene, rows = document["scene"], document["rows"]
        assert page.evaluate("state.run.answer.rows") == rows
        k = int(share * (len(rows) - 1))
        drawn = show_frame(page, k)
        # the hook: this model's elements, in order, at the slider's sample
        assert drawn["sample"] == rows[k] and drawn["time"] == scene["times"][k]
        listed = [(e["kind"], e["name"]) for panel in scene["panels"] for e in panel["elements"]]
        assert [(e["kind"], e["name"]) for e in drawn["elements"]] == listed
        assert page.input_value("[data-testid=time]") == str(k)
        shown = page.inner_text("#time-shown").split()  # "t = 1.234 s": the sample's time
        assert float(shown[2]) == pytest.approx(document["columns"]["t"][rows[k]], rel=1e-3)
        canvas = page.evaluate("[canvas.width, canvas.height]")
        if name == "rolling_disc":
            check_shape(page, scene, canvas, first(scene, "body", "line"), k)  # the rim
            check_shape(page, scene, canvas, first(scene, "ground", "line"), k)  # the floor
        elif name == "heavy_symmetric_top":
            check_shape(page, scene, canvas, first(scene, "body", "line"), k)  # its outline
            p, e, _ = first(scene, "body_axes", "line")
            for axis in range(3):  # x, y, z in red, green, blue
                check_shape(page, scene, canvas, (p, e, axis), k)
        elif name == "two_mesh_circuit":
            for mesh in range(2):  # each mesh current's arrow, as long as its share of the largest
                p, e, s = first(scene, "current", "line")
                check_shape(page, scene, canvas, (p, e + mesh, s), k)
            check_shape(page, scene, canvas, first(scene, "capacitor", "line"), k)
        else:  # the bob where (l sin theta, -l cos theta) puts it at the slider's sample
            theta = document["columns"]["theta"][rows[k]]
            p, e, s = first(scene, "particle", "dot")
            panel = scene["panels"][p]
            box = boxes(len(scene["panels"]), *canvas)[p]
            u, v = to_pixels(panel, box, [math.sin(theta), -math.cos(theta)])
            pixels = page.evaluate(PIXELS, [round(float(u)), round(float(v)), 1])
            assert ink_of(pixels, panel["elements"][e]["shapes"][s]["color"]) >= 0.9
            check_shape(page, scene, canvas, first(scene, "rod", "line"), k)
        page.locator("[data-testid=simulation-panel]").screenshot(
            path=str(ARTIFACTS / f"scene_{name}_{size}.png")
        )
    assert not errors
    page.context.close()


def test_an_impact_flashes_its_frame(browser: Any, page_server: str) -> None:
    page, errors = open_page(browser, page_server + "/", "desktop")
    page.select_option("[data-testid=examples]", "bouncing_ball")
    settled(page, "bouncing_ball")
    scene = page.evaluate("state.run.answer.scene")
    impact = scene["impacts"][0]
    canvas = page.evaluate("[canvas.width, canvas.height]")
    x, y, side = boxes(len(scene["panels"]), *canvas)[0]
    border = [int(x + side / 2), int(y + TITLE)]  # the top edge of the panel's frame
    for k, flashed in ((impact["frame"], True), (max(impact["frame"] - 2, 0), False)):
        drawn = show_frame(page, k)
        assert (drawn["flash"] == impact["label"]) is flashed
        red = ink_of(page.evaluate(PIXELS, [*border, 1]), "#d62728")
        assert (red >= 0.9) is flashed, (k, red)
    panel = page.locator("[data-testid=simulation-panel]")
    panel.screenshot(path=str(ARTIFACTS / "scene_impact.png"))
    assert not errors
    page.context.close()


def test_a_scene_of_two_panels_stacks_them(browser: Any, page_server: str) -> None:
    page, errors = open_page(browser, page_server + "/", "phone")
    page.select_option("[data-testid=examples]", "servo_system")  # a circuit and a rotor
    settled(page, "servo_system")
    scene, rows = page.evaluate("[state.run.answer.scene, state.run.answer.rows]")
    assert len(scene["panels"]) == 2 and scene["panels"][0]["title"] == "circuit"
    canvas = page.evaluate("[canvas.width, canvas.height]")
    assert canvas == [380, 600]  # one square a panel, one above the other
    k = len(rows) // 3
    drawn = show_frame(page, k)
    assert {e["panel"] for e in drawn["elements"]} == {0, 1}
    check_shape(page, scene, canvas, first(scene, "current", "line"), k)
    check_shape(page, scene, canvas, first(scene, "coordinates", "dot"), k)
    page.locator("[data-testid=simulation-panel]").screenshot(
        path=str(ARTIFACTS / "scene_servo_system_phone.png")
    )
    assert not errors
    page.context.close()


def test_the_gas_draws_its_disks_where_the_run_puts_them_inside_its_box(
    browser: Any, page_server: str
) -> None:
    page, errors = open_page(browser, page_server + "/", "desktop")
    page.select_option("[data-testid=examples]", "simple_pendulum")
    settled(page, "simple_pendulum")
    assert page.locator("[data-testid=size-field]").is_hidden()  # a model file of its own size
    page.select_option("[data-testid=examples]", "hard_disk_gas")
    settled(page, "hard_disk_gas")
    assert page.input_value("[data-testid=example-size]") == "4"
    page.fill("[data-testid=example-size]", "9")  # nine disks: a new model, written for it
    page.dispatch_event("[data-testid=example-size]", "change")  # once more: loaded once
    text = examples.model_text("hard_disk_gas", 9)
    page.wait_for_function("(text) => document.getElementById('editor').value === text",
                           arg=text, timeout=60_000)  # fmt: skip
    page.wait_for_function(
        """() => document.getElementById('simulation-panel').dataset.version ===
                 document.body.dataset.version && !document.querySelector('.panel.stale')""",
        timeout=120_000,
    )
    version = page.evaluate("document.body.dataset.version")
    status, body = run("simulate", text, "yaml", {})
    assert status == 200
    document = json.loads(body)
    scene, rows, columns = document["scene"], document["rows"], document["columns"]
    assert page.evaluate("state.run.answer.rows") == rows
    assert page.evaluate("document.body.dataset.version") == version
    counted = document["summary"]["impacts_summary"].split(" (")[0]  # "31 impacts"
    assert counted.endswith("impacts") and counted in page.inner_text("[data-testid=summary]")
    k = len(rows) // 2
    drawn = show_frame(page, k)
    # the panel is the gas's: its walls and disks, none of the pendulum's
    (panel,) = scene["panels"]
    listed = [(e["kind"], e["name"]) for e in panel["elements"]]
    assert [(e["kind"], e["name"]) for e in drawn["elements"]] == listed
    assert [kind for kind, _ in listed].count("particle") == 9 and (
        "rod",
        "origin-bob",
    ) not in listed
    canvas = page.evaluate("[canvas.width, canvas.height]")
    box = boxes(1, *canvas)[0]
    side, radius = 1.0, 1.0 / 3 / 5  # the box L = 1, nine disks of a fifth of L / 3
    for disk in range(1, 10):  # each centre and rim where the run's columns put them
        x, y = columns[f"x{disk}"][rows[k]], columns[f"y{disk}"][rows[k]]
        assert radius <= x <= side - radius and radius <= y <= side - radius
        color = next(e for e in panel["elements"] if e["name"] == f"disk{disk}")["shapes"][1]
        u, v = to_pixels(panel, box, [x, y])
        centre = page.evaluate(PIXELS, [round(float(u)), round(float(v)), 1])
        assert ink_of(centre, color["color"]) >= 0.9, disk
        angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
        rim = to_pixels(panel, box, np.c_[x + radius * np.cos(angles), y + radius * np.sin(angles)])
        inked = [ink_of(page.evaluate(PIXELS, [round(float(a)), round(float(b)), 1]),
                        color["color"]) for a, b in rim]  # fmt: skip
        assert sum(share >= 0.6 for share in inked) >= 6, (disk, inked)
    for wall in ([0, 0.5], [side, 0.5], [0.5, 0], [0.5, side]):  # the box's sides, in grey
        along = (
            np.array([[0, 0.25], [0, 0.75]]) if wall[1] == 0.5 else np.array([[0.25, 0], [0.75, 0]])
        )
        points = to_pixels(panel, box, np.array(wall) + (along - along.mean(axis=0)))
        shares = [ink_of(page.evaluate(PIXELS, [round(float(a)), round(float(b)), 1]), "#4d4d4d")
                  for a, b in points]  # fmt: skip
        assert max(shares) >= 0.9, (wall, shares)
    page.locator("[data-testid=simulation-panel]").screenshot(
        path=str(ARTIFACTS / "scene_hard_disk_gas.png")
    )
    assert not errors
    page.context.close()
