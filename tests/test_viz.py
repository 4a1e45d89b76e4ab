"""Tests for proxemic.viz (the numpy top-down renderer and the matplotlib figures)."""

from __future__ import annotations

import math
import pathlib
import sys
from typing import Any

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "python"))

from proxemic.palette import (
    FLOOR_COLOR,
    INTERACTION_COLOR,
    OBJECT_COLORS,
    OUTSIDE_COLOR,
    PERSON_COLOR,
    PERSON_TICK,
    ROBOT_PALETTE,
    WALL_COLOR,
    ZONE_COLORS,
)
from proxemic.viz import TopDownRenderer, format_table, plot_episodes

W, H = 640, 480


# ----------------------------------------------------------------------------------------------
# Fixture: a 10 x 8 m room, the shape the Rust core hands to Python (polygons precomputed)
# ----------------------------------------------------------------------------------------------


def _rect(cx: float, cy: float, theta: float, depth: float, width: float) -> list[list[float]]:
    c, s = math.cos(theta), math.sin(theta)
    out = []
    for lx, ly in (
        (-depth / 2, -width / 2),
        (depth / 2, -width / 2),
        (depth / 2, width / 2),
        (-depth / 2, width / 2),
    ):
        out.append([cx + c * lx - s * ly, cy + s * lx + c * ly])
    return out


def _wall(p0: tuple[float, float], p1: tuple[float, float], thickness: float = 0.2) -> dict[str, Any]:
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    poly = _rect((p0[0] + p1[0]) / 2, (p0[1] + p1[1]) / 2, math.atan2(dy, dx), math.hypot(dx, dy), thickness)
    return {"from": list(p0), "to": list(p1), "thickness": thickness, "height": 2.5, "polygon": poly}


def _circle(cx: float, cy: float, r: float, n: int = 32) -> list[list[float]]:
    return [[cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n)] for k in range(n)]


def make_scenario() -> dict[str, Any]:
    """A 10 x 8 m room: 4 outer walls, an interior wall at x = 6 with a doorway at y in (3, 4)."""
    walls = [
        _wall((0, 0), (10, 0)),
        _wall((10, 0), (10, 8)),
        _wall((10, 8), (0, 8)),
        _wall((0, 8), (0, 0)),
        _wall((6, 0), (6, 3)),
        _wall((6, 4), (6, 8)),
    ]
    # painting on the top wall facing down (-y); trapezoid 2 m deep, 1.2 m -> 2.4 m wide
    painting_pose = [3.0, 7.85, -math.pi / 2]
    trapezoid = [[2.4, 7.8], [1.8, 5.8], [4.2, 5.8], [3.6, 7.8]]  # CCW
    objects = [
        {
            "name": "painting_1",
            "kind": "painting",
            "pose": painting_pose,
            "size": [0.1, 1.2],
            "radius": None,
            "height": 1.8,
            "solid": True,
            "footprint": _rect(*painting_pose, 0.1, 1.2),
            "interaction": {
                "shape": "trapezoid",
                "length": 2.0,
                "near_width": 1.2,
                "far_width": 2.4,
                "polygon": trapezoid,
            },
        },
        {
            "name": "bench_1",
            "kind": "bench",
            "pose": [3.0, 3.5, 0.0],
            "size": [0.5, 1.6],
            "radius": None,
            "height": 0.45,
            "solid": True,
            "footprint": _rect(3.0, 3.5, 0.0, 0.5, 1.6),
            "interaction": None,
        },
        {
            "name": "table_1",
            "kind": "round_table",
            "pose": [8.0, 2.0, 0.0],
            "size": [1.0, 1.0],
            "radius": 0.5,
            "height": 0.75,
            "solid": True,
            "footprint": _circle(8.0, 2.0, 0.5),
            "interaction": {"shape": "circle", "radius": 1.2, "polygon": _circle(8.0, 2.0, 1.2)},
        },
    ]
    persons = [
        {
            "name": "person_0",
            "behaviour": "walker",
            "pose": [1.0, 1.0, 0.0],
            "route": [[1.0, 1.0], [5.0, 1.0], [5.0, 6.0]],
            "speed": 1.0,
            "dwell": 0.0,
            "radius": 0.2,
            "height": 1.7,
            "group": None,
        },
        {
            "name": "person_1",
            "behaviour": "standing",
            "pose": [3.0, 6.5, math.pi / 2],
            "route": [],
            "speed": 1.0,
            "dwell": 0.0,
            "radius": 0.2,
            "height": 1.7,
            "group": 0,
        },
        {
            "name": "person_2",
            "behaviour": "standing",
            "pose": [3.5, 6.5, math.pi / 2],
            "route": [],
            "speed": 1.0,
            "dwell": 0.0,
            "radius": 0.2,
            "height": 1.7,
            "group": 0,
        },
    ]
    robots = [
        {
            "name": "robot_0",
            "start": [1.0, 2.0, 0.0],
            "goal": [9.0, 6.0],
            "planner": "astar",
            "radius": 0.24,
            "max_speed": 0.55,
        }
    ]
    return {
        "source": "tests/room.toml",
        "scene": {
            "name": "room",
            "description": "test room",
            "bounds": [0.0, 0.0, 10.0, 8.0],
            "resolution": 0.1,
            "start_time": 36000.0,
            "control_hz": 10.0,
            "physics_hz": 100.0,
            "wall_height": 2.5,
        },
        "walls": walls,
        "objects": objects,
        "persons": persons,
        "robots": robots,
        "episode": {},
        "sensors": {},
        "reward": {},
    }


@pytest.fixture(scope="module")
def scenario() -> dict[str, Any]:
    return make_scenario()


@pytest.fixture(scope="module")
def renderer(scenario: dict[str, Any]) -> TopDownRenderer:
    return TopDownRenderer(scenario, width=W, height=H, margin=0.5)


def pix(r: TopDownRenderer, img: np.ndarray, x: float, y: float) -> tuple[int, int, int]:
    """The colour of the pixel containing world point (x, y)."""
    col, row = r.world_to_pixel(np.array([[x, y]]))[0]
    px = img[math.floor(row), math.floor(col)]
    return (int(px[0]), int(px[1]), int(px[2]))


def no_people() -> np.ndarray:
    return np.zeros((0, 4))


# ----------------------------------------------------------------------------------------------
# TopDownRenderer
# ----------------------------------------------------------------------------------------------


def test_frame_shape_and_dtype(renderer: TopDownRenderer) -> None:
    frame = renderer.render(np.array([[1.0, 2.0, 0.0]]), np.array([[4.5, 2.0, 0.0, 0.2]]))
    assert frame.shape == (H, W, 3)
    assert frame.dtype == np.uint8


def test_world_to_pixel_fits_bounds_with_margin_and_keeps_aspect(renderer: TopDownRenderer) -> None:
    # world extent with margin is 11 x 9 m; height is the limiting axis: 480 / 9 px per metre
    s = H / 9.0
    assert renderer.scale == pytest.approx(s)
    off = (W - 11.0 * s) / 2.0
    corners = renderer.world_to_pixel(np.array([[-0.5, 8.5], [10.5, -0.5], [0.0, 8.0], [10.0, 0.0]]))
    np.testing.assert_allclose(corners[0], [off, 0.0], atol=1e-9)  # top-left of the view -> image top
    np.testing.assert_allclose(corners[1], [W - off, H], atol=1e-9)  # bottom-right -> image bottom
    np.testing.assert_allclose(corners[2], [off + 0.5 * s, 0.5 * s], atol=1e-9)  # bounds corner inside margin
    np.testing.assert_allclose(corners[3], [W - off - 0.5 * s, H - 0.5 * s], atol=1e-9)
    # aspect: 1 m along x and along y are the same number of pixels
    p = renderer.world_to_pixel(np.array([[2.0, 3.0], [3.0, 3.0], [2.0, 4.0]]))
    assert abs(p[1, 0] - p[0, 0]) == pytest.approx(abs(p[2, 1] - p[0, 1]))
    # round trip
    pts = np.array([[1.25, 7.5], [9.0, 0.3]])
    np.testing.assert_allclose(renderer.pixel_to_world(renderer.world_to_pixel(pts)), pts)


def test_world_to_pixel_fills_width_when_width_limits() -> None:
    r = TopDownRenderer(make_scenario(), width=200, height=400, margin=0.0)
    c = r.world_to_pixel(np.array([[0.0, 8.0], [10.0, 0.0]]))
    assert c[0, 0] == pytest.approx(0.0)
    assert c[1, 0] == pytest.approx(200.0)
    assert c[1, 1] - c[0, 1] == pytest.approx(8.0 * 20.0)  # 20 px/m on both axes
    assert c[0, 1] == pytest.approx((400 - 160) / 2)  # centred vertically


def test_y_up(renderer: TopDownRenderer) -> None:
    p = renderer.world_to_pixel(np.array([[5.0, 1.0], [5.0, 6.0]]))
    assert p[1, 1] < p[0, 1]
    assert p[1, 0] == pytest.approx(p[0, 0])


def test_static_background_colours(renderer: TopDownRenderer) -> None:
    bg = renderer.background
    assert pix(renderer, bg, 5.0, 0.0) == WALL_COLOR  # outer wall centre line
    assert pix(renderer, bg, 6.0, 1.5) == WALL_COLOR  # interior wall
    assert pix(renderer, bg, 6.0, 3.5) == FLOOR_COLOR  # the doorway is open
    assert pix(renderer, bg, 4.5, 2.0) == FLOOR_COLOR
    assert pix(renderer, bg, -0.4, 4.0) == OUTSIDE_COLOR  # margin
    assert pix(renderer, bg, 3.0, 3.5) == OBJECT_COLORS["bench"]
    assert pix(renderer, bg, 8.0, 2.0) == OBJECT_COLORS["round_table"]
    # interaction spaces are tinted floor: between the floor colour and the tint
    for x, y in ((3.0, 6.0), (8.0, 2.0 + 0.9)):
        c = np.array(pix(renderer, bg, x, y), dtype=float)
        f, t = np.array(FLOOR_COLOR, dtype=float), np.array(INTERACTION_COLOR, dtype=float)
        assert not np.array_equal(c, f)
        assert np.all(c >= np.minimum(f, t) - 1) and np.all(c <= np.maximum(f, t) + 1)
    # inside the bounding boxes of the trapezoid and the circle but outside the shapes: plain floor
    assert pix(renderer, bg, 2.0, 7.5) == FLOOR_COLOR
    assert pix(renderer, bg, 4.0, 7.5) == FLOOR_COLOR
    assert pix(renderer, bg, 7.05, 1.05) == FLOOR_COLOR
    assert not bg.flags.writeable


def test_person_and_robot_pixels(renderer: TopDownRenderer) -> None:
    people = np.array([[4.5, 2.0, 0.0, 0.2], [2.0, 5.0, math.pi, 0.3]])
    robots = np.array([[1.5, 2.0, 0.0], [8.0, 5.0, math.pi / 2]])
    frame = renderer.render(robots, people)
    assert pix(renderer, frame, 4.5, 2.0) == PERSON_COLOR
    assert pix(renderer, frame, 2.0, 5.0) == PERSON_COLOR
    assert pix(renderer, frame, 1.5, 2.0) == ROBOT_PALETTE[0]
    assert pix(renderer, frame, 8.0, 5.0) == ROBOT_PALETTE[1]
    # the disc has the person's radius: inside at 0.15 m, background at 0.3 m
    assert pix(renderer, frame, 4.5, 2.15) == PERSON_COLOR
    assert pix(renderer, frame, 4.5, 2.3) == FLOOR_COLOR


def test_heading_tick_shows_facing(renderer: TopDownRenderer) -> None:
    for theta, dx, dy in ((0.0, 1.0, 0.0), (math.pi, -1.0, 0.0), (math.pi / 2, 0.0, 1.0)):
        frame = renderer.render(np.zeros((0, 3)), np.array([[4.5, 2.0, theta, 0.25]]))
        ahead = pix(renderer, frame, 4.5 + 0.15 * dx, 2.0 + 0.15 * dy)
        behind = pix(renderer, frame, 4.5 - 0.15 * dx, 2.0 - 0.15 * dy)
        assert ahead == PERSON_TICK, theta
        assert behind == PERSON_COLOR, theta


def test_background_not_mutated_across_calls(renderer: TopDownRenderer) -> None:
    before = renderer.background.copy()
    f1 = renderer.render(np.zeros((0, 3)), np.array([[4.5, 2.0, 0.0, 0.2]]))
    f2 = renderer.render(np.zeros((0, 3)), np.array([[2.0, 5.0, 0.0, 0.2]]))
    assert pix(renderer, f1, 4.5, 2.0) == PERSON_COLOR
    assert pix(renderer, f2, 4.5, 2.0) == FLOOR_COLOR
    assert pix(renderer, f2, 2.0, 5.0) == PERSON_COLOR
    assert pix(renderer, f1, 4.5, 2.0) == PERSON_COLOR  # f1 is its own array
    assert not np.shares_memory(f1, f2)
    np.testing.assert_array_equal(renderer.background, before)


def test_empty_inputs_give_background(renderer: TopDownRenderer) -> None:
    frame = renderer.render(np.zeros((0, 3)), no_people())
    np.testing.assert_array_equal(frame, renderer.background)
    frame = renderer.render(np.zeros((0, 3)), np.array([]))
    np.testing.assert_array_equal(frame, renderer.background)


def test_goals_paths_trails(renderer: TopDownRenderer) -> None:
    robots = np.array([[1.0, 2.0, 0.0]])
    goals = np.array([[9.0, 6.0]])
    path = np.array([[1.0, 2.0], [1.0, 6.5]])
    trail = np.array([[2.0, 1.0], [5.0, 1.0]])
    frame = renderer.render(robots, no_people(), goals=goals, paths=[path], trails=[trail])
    blue = ROBOT_PALETTE[0]
    light = tuple(round(0.5 * c + 0.5 * 255) for c in blue)
    assert pix(renderer, frame, 3.5, 1.0) == light  # solid trail, lightened robot colour
    assert pix(renderer, frame, 9.0, 6.0) == blue  # centre of the goal cross
    # the dashed path: some but not all pixels along it are the robot colour
    col = renderer.world_to_pixel(np.array([[1.0, 0.0]]))[0, 0]
    rows = np.arange(*sorted(int(v) for v in renderer.world_to_pixel(np.array([[1, 3.0], [1, 6.0]]))[:, 1]))
    on = np.all(frame[rows, math.floor(col)] == blue, axis=1)
    assert 0.3 < on.mean() < 0.7


def test_robustness_offscreen_nan_and_shapes(renderer: TopDownRenderer) -> None:
    people = np.array([[1e6, -1e6, 0.0, 0.2], [np.nan, 1.0, 0.0, 0.2], [4.5, 2.0, 0.0, 0.2]])
    frame = renderer.render(
        np.array([[-50.0, 3.0, 1.0]]), people, paths=[np.array([[-1e6, 4.0], [1e6, 4.0]])], trails=[None]
    )
    assert pix(renderer, frame, 4.5, 2.0) == PERSON_COLOR
    assert pix(renderer, frame, 2.0, 4.0) == ROBOT_PALETTE[0] or pix(renderer, frame, 2.2, 4.0) == ROBOT_PALETTE[0]
    with pytest.raises(ValueError):
        renderer.render(np.zeros((2, 2)), no_people())
    with pytest.raises(ValueError):
        renderer.render(np.zeros((0, 3)), np.zeros((3, 2)))


def test_render_is_deterministic(scenario: dict[str, Any]) -> None:
    rng = np.random.default_rng(0)
    people = np.column_stack([rng.uniform(0, 10, 20), rng.uniform(0, 8, 20), rng.uniform(-3, 3, 20), np.full(20, 0.2)])
    a = TopDownRenderer(scenario).render(np.array([[1.0, 2.0, 0.3]]), people)
    b = TopDownRenderer(scenario).render(np.array([[1.0, 2.0, 0.3]]), people)
    np.testing.assert_array_equal(a, b)


# ----------------------------------------------------------------------------------------------
# Overlays
# ----------------------------------------------------------------------------------------------


def test_object_spaces_coloured_by_cost(renderer: TopDownRenderer) -> None:
    robots = np.zeros((0, 3))
    bare = renderer.render(robots, no_people())
    idle = renderer.render(robots, no_people(), object_costs={"painting_1": 1.5, "table_1": 1.5})
    busy = renderer.render(robots, no_people(), object_costs={"painting_1": 3.5, "table_1": 1.5})
    inside = (3.0, 6.2)  # in the painting's trapezoid
    assert pix(renderer, busy, *inside) != pix(renderer, idle, *inside) != pix(renderer, bare, *inside)
    # higher R(t) is redder: more red than green, and less green than at the idle cost
    r, g, _ = pix(renderer, busy, *inside)
    assert r > g + 60 and g < pix(renderer, idle, *inside)[1]
    # the table's space keeps its colour when only the painting's cost changes
    assert pix(renderer, busy, 8.0, 3.0) == pix(renderer, idle, 8.0, 3.0)
    # objects drawn on top of their spaces and the plain floor are untouched
    assert pix(renderer, busy, 8.0, 2.0) == pix(renderer, bare, 8.0, 2.0)
    assert pix(renderer, busy, 5.0, 5.0) == FLOOR_COLOR
    # an object missing from the mapping is drawn at the idle cost
    missing = renderer.render(robots, no_people(), object_costs={"table_1": 1.5})
    np.testing.assert_array_equal(missing, idle)


def test_zone_rings_at_the_given_radii(renderer: TopDownRenderer) -> None:
    person = np.array([[2.0, 4.0, 0.0, 0.2]])
    radii = (0.45, 1.2, 2.0)
    frame = renderer.render(np.zeros((0, 3)), person, zones=radii)
    plain = renderer.render(np.zeros((0, 3)), person)
    for k, rad in enumerate(radii):
        for ang in (0.0, 1.3, math.pi):
            x, y = 2.0 + rad * math.cos(ang), 4.0 + rad * math.sin(ang)
            near = (-0.04, -0.02, 0.0, 0.02, 0.04)  # within two pixels (53 px/m)
            found = {pix(renderer, frame, x + dx, y + dy) for dx in near for dy in near}
            assert ZONE_COLORS[k] in found, (rad, ang)
    # between the rings the floor shows
    assert pix(renderer, frame, 2.0 + 1.6, 4.0) == FLOOR_COLOR == pix(renderer, plain, 2.0 + 1.6, 4.0)


def test_groups_fill_the_o_space_and_skip_singletons(renderer: TopDownRenderer) -> None:
    people = np.array([[3.0, 3.0, 0.0, 0.2], [4.4, 3.0, math.pi, 0.2], [8.0, 6.0, 0.0, 0.2]])
    plain = renderer.render(np.zeros((0, 3)), people)
    grouped = renderer.render(np.zeros((0, 3)), people, groups=[[0, 1], [2]])
    centre = (3.7, 3.0)  # between the two members: the o-space
    c = pix(renderer, grouped, *centre)
    assert pix(renderer, plain, *centre) == FLOOR_COLOR and c != FLOOR_COLOR
    assert c[2] > c[1]  # tinted towards the group colour (purple: blue above green)
    # a one-member group draws nothing around its member
    assert pix(renderer, grouped, 8.0, 6.6) == pix(renderer, plain, 8.0, 6.6)


# ----------------------------------------------------------------------------------------------
# Plots
# ----------------------------------------------------------------------------------------------


def _episodes(p: int) -> list[dict[str, Any]]:
    t = np.linspace(0.0, 1.0, 50)
    robot_a = np.column_stack([1 + 8 * t, 2 + 4 * t**2, np.zeros_like(t)])
    robot_b = np.column_stack([1 + 4 * t, 2 + 1.5 * t, np.zeros_like(t)])
    people = np.zeros((50, p, 2))
    for k in range(p):
        people[:, k] = np.column_stack([1 + 4 * t + k, 1 + 0 * t + k])
    return [
        {
            "label": "astar",
            "robot": robot_a,
            "people": people,
            "path": np.array([[1, 2], [6, 3.5], [9, 6]]),
            "outcome": "success",
            "color": "#ff00ff",
        },
        {"label": "social", "robot": robot_b, "people": people, "path": None, "outcome": "collision"},
        {"label": "slow", "robot": robot_b[:10], "people": None, "path": None, "outcome": "timeout"},
    ]


def test_plot_episodes_writes_png(tmp_path: pathlib.Path, scenario: dict[str, Any]) -> None:
    import matplotlib.image as mpimg

    out = plot_episodes(scenario, _episodes(3), tmp_path / "sub" / "ep.png", title="room")
    assert out == tmp_path / "sub" / "ep.png"
    assert out.stat().st_size > 1000
    img = mpimg.imread(out)
    assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100
    rgb = img[..., :3]
    assert float(rgb.std()) > 0.01
    # the magenta trajectory of the first episode is drawn
    magenta = (rgb[..., 0] > 0.9) & (rgb[..., 1] < 0.15) & (rgb[..., 2] > 0.9)
    assert magenta.sum() > 50
    # deterministic output
    again = plot_episodes(scenario, _episodes(3), tmp_path / "ep2.png", title="room")
    assert again.read_bytes() == out.read_bytes()


def test_plot_episodes_without_people_or_path(tmp_path: pathlib.Path, scenario: dict[str, Any]) -> None:
    import matplotlib.image as mpimg

    eps = _episodes(0)
    assert eps[0]["people"].shape == (50, 0, 2)
    for e in eps:
        e["path"] = None
    out = plot_episodes(scenario, eps, str(tmp_path / "ep0.png"))
    img = mpimg.imread(out)
    assert img.ndim == 3 and float(img[..., :3].std()) > 0.01


def test_format_table_exact() -> None:
    rows = [
        {"planner": "astar", "success": 0.9, "time": 12.34567, "steps": 120, "collided": False, "note": None},
        {"planner": "social", "success": 1.0, "time": None, "steps": 98, "collided": True, "note": "a|b"},
    ]
    expected = (
        "| planner | success | time | steps | collided | note |\n"
        "| --- | --- | --- | --- | --- | --- |\n"
        "| astar | 0.900 | 12.346 | 120 | no | \u2013 |\n"
        "| social | 1.000 | \u2013 | 98 | yes | a\\|b |"
    )
    assert format_table(rows, ["planner", "success", "time", "steps", "collided", "note"]) == expected
    assert format_table(rows[:1], ["time", "missing"], floatfmt=".1f") == (
        "| time | missing |\n| --- | --- |\n| 12.3 | \u2013 |"
    )
