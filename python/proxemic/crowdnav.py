"""CrowdNav's protocol, run and counted as CrowdNav's code does, beside its measured figures.

Circle- and square-crossing scenes with ORCA people, run and counted as CrowdNav's own code runs and
counts them, beside CrowdNav's measured figures and the literature's.

Chen, Liu, Kreiss, Alahi, "Crowd-robot interaction: crowd-aware robot navigation with
attention-based deep reinforcement learning", ICRA 2019 (https://github.com/vita-epfl/CrowdNav).

A scene is named ``crowdnav/<family>`` with ``?humans=N&visible=true|false&seed=S&drive=D``
(family ``circle_crossing`` or ``square_crossing``; defaults 5 people, robot invisible, seed 0, the
holonomic robot; ``drive=differential`` is CrowdNav's unicycle robot); the core generates it
(``rust/proxemic-core/src/scenario/generate/crowdnav``) and runs its episode kinematically as
CrowdNav does (``rust/proxemic-core/src/world/crowdnav.rs``): ORCA people, time step 0.25 s,
CrowdNav's order of timeout, collision, goal and discomfort checks. The suite (:func:`run_suite`,
``proxemic eval --suite crowdnav``) runs the four settings of :data:`SETTINGS`, with the holonomic
and the unicycle robot (:data:`DRIVES`), on scene seeds ``seed, seed + 1, ...`` with every built-in
planner of :data:`PLANNERS` and a user's policies (:func:`policy_episodes`: the policy drives the
robot through the env's observation and action spaces, in the same kinematic episodes), and
:func:`table_text` prints the result beside CrowdNav's own run (``data/crowdnav/reference.json``,
measured with its code; provenance in the file) and the literature's figures. See ``docs/crowdnav.md``.
"""

from __future__ import annotations

import dataclasses
import functools
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from proxemic import _core, markdown
from proxemic.errors import input_error
from proxemic.policy import PolicyRef
from proxemic.scenarios import CROWDNAV_PREFIX

#: Prefix of a CrowdNav scene's name.
PREFIX = CROWDNAV_PREFIX
#: The suite's name for ``proxemic eval --suite``.
SUITE = "crowdnav"
#: The planners the protocol's kinematic episodes run: every built-in planner (``astar_orca`` is
#: CrowdNav's ORCA robot; the others drive through the core's world set to each step's state).
PLANNERS: tuple[str, ...] = tuple(_core.CROWDNAV_PLANNERS)
#: First scene seed of the suite's default run: the test split's first generated scene seed
#: (``proxemic.splits.TEST_SCENE_SEEDS``); nothing was tuned on these scenes.
TEST_SEED = 10_000
#: Episodes per setting of CrowdNav's test phase.
EPISODES = 500
#: The robot's drives the suite runs: CrowdNav's holonomic robot (its figures, the agreement check)
#: and its unicycle (``drive=differential``: a speed and a turn of at most π/4 per step, turn first).
DRIVES: tuple[str, ...] = ("holonomic", "differential")

_REFERENCE = Path(__file__).parent / "data" / "crowdnav" / "reference.json"


@dataclass(frozen=True)
class Setting:
    """One of the protocol's four settings."""

    #: Key in the reference data.
    key: str
    #: Scene family.
    family: str
    #: People.
    humans: int
    #: Whether the people see the robot.
    visible: bool
    #: The robot's drive, one of :data:`DRIVES`.
    drive: str = "holonomic"

    @property
    def label(self) -> str:
        """A short label: family, people, visibility, and the unicycle when it is one."""
        unicycle = ", unicycle" if self.drive == "differential" else ""
        seen = "visible" if self.visible else "invisible"
        return f"{self.family.split('_')[0]} {self.humans}, robot {seen}{unicycle}"

    def spec(self, seed: int) -> str:
        """The scene name of this setting with scene seed `seed`."""
        vis = "&visible=true" if self.visible else ""
        drive = f"&drive={self.drive}" if self.drive != "holonomic" else ""
        return f"{PREFIX}{self.family}?humans={self.humans}{vis}&seed={seed}{drive}"

    def with_drive(self, drive: str) -> Setting:
        """This setting with the robot's `drive`.

        Raises:
            InputError: `drive` is not one of :data:`DRIVES`.
        """
        if drive not in DRIVES:
            raise input_error("drive", f"one of {list(DRIVES)}", drive)
        return dataclasses.replace(self, drive=drive)


#: The settings of the agreement check: circle crossing with 5 people (robot invisible and
#: visible), with 20 (invisible), square crossing with 5 (invisible).
SETTINGS: tuple[Setting, ...] = (
    Setting("circle5_invisible", "circle_crossing", 5, False),
    Setting("circle5_visible", "circle_crossing", 5, True),
    Setting("circle20_invisible", "circle_crossing", 20, False),
    Setting("square5_invisible", "square_crossing", 5, False),
)

#: The agreement required with CrowdNav's own run: success and collision rates within this.
RATE_TOLERANCE = 0.06
#: ... and the mean navigation time of successes within this fraction.
TIME_TOLERANCE = 0.10

#: The setup differences that remain between our run and CrowdNav's (shown beside the table).
DIFFERENCES: tuple[str, ...] = (
    "scenes: the same distributions drawn from our seeds (ChaCha8), not CrowdNav's numpy test cases one for one",
    "positions rounded to centimetres in the scene file (CrowdNav keeps full precision)",
    "ORCA: proxemic's own implementation (plain RVO2 settings: no perturbation, no passing-side tilt), "
    "not the RVO2 library",
    "the other built-in planners and a user's policy see the robot and the people through proxemic's world "
    "(its perception, social maps and sensors: lidar and the 8 nearest people), not CrowdNav's joint state; "
    "their commands are limited by the robot's limits with an acceleration that reaches any velocity in one step",
    "the unicycle: CrowdNav's ORCA robot is holonomic only, so its rows have no CrowdNav figures; astar_orca's "
    "unicycle turns toward ORCA's velocity by at most π/4 a step and moves at its projection on the new heading "
    "(proxemic's rule)",
)


@functools.cache
def _reference_text() -> str:
    return _REFERENCE.read_text(encoding="utf-8")


def reference() -> dict[str, Any]:
    """CrowdNav's measured figures and the literature's (``data/crowdnav/reference.json``, a fresh copy)."""
    data: dict[str, Any] = json.loads(_reference_text())
    return data


def episodes(setting: Setting, seeds: Sequence[int], planner: str = "astar_orca") -> list[dict[str, Any]]:
    """The episode records of `setting` on scene seeds `seeds` with the built-in `planner`.

    Raises:
        InputError: `planner` is not one of :data:`PLANNERS`.
    """
    if planner not in PLANNERS:
        raise input_error("planner", f"one of {list(PLANNERS)}", planner)
    return _core.crowdnav_episodes([setting.spec(s) for s in seeds], planner)


def policy_episodes(setting: Setting, seeds: Sequence[int], policy: PolicyRef) -> list[dict[str, Any]]:
    """The episode records of `setting` on scene seeds `seeds` driven by a user's `policy`.

    The policy is built as ``proxemic eval --policy`` builds it (its factory called with the env's
    observation and action spaces of the setting's scene) and drives the robot in the protocol's
    kinematic episodes: every step it gets the env's observation of the instant and its action
    (normalised, robot frame) is limited as the env limits it, cut to 1 m/s and applied at once.
    ``reset(seed)`` is called with each scene seed.

    Raises:
        InputError: The policy cannot be built, or returns an action that is not 3 finite numbers.
        PolicyError: The policy raised.
    """
    from proxemic.evaluation.episodes import policy_env

    env, actor = policy_env(setting.spec(seeds[0]) if seeds else setting.spec(TEST_SEED), policy)
    ws = env.unwrapped.ws

    def act(row: Any) -> tuple[float, ...]:
        ws.out[:] = row
        return tuple(actor(ws.observation(0, robots=False)).tolist())

    records = []
    for seed in seeds:
        actor.reset(seed)
        records.extend(_core.crowdnav_policy_episodes([setting.spec(seed)], act))
    return records


def summarise(records: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """CrowdNav's explorer's figures over episode records.

    Counts, rates, mean navigation time of successes (the time limit 25 s when there is none),
    discomfort frequency (discomfort steps over the episodes' total time in steps, a timeout
    counting 25 s).
    """
    n = len(records)
    if n == 0:
        raise input_error("records", "at least one episode record", "none")
    by = {o: [r for r in records if r["outcome"] == o] for o in ("success", "collision", "timeout")}
    times = [r["time"] for r in by["success"]]
    steps = sum(r["time"] for r in records) / 0.25
    danger = sum(r["discomfort_steps"] for r in records)
    return {
        "episodes": n,
        "success": len(by["success"]),
        "collision": len(by["collision"]),
        "timeout": len(by["timeout"]),
        "success_rate": len(by["success"]) / n,
        "collision_rate": len(by["collision"]) / n,
        "mean_nav_time_s": sum(times) / len(times) if times else 25.0,
        "discomfort_frequency": danger / steps,
    }


def measured(key: str) -> dict[str, Any]:
    """CrowdNav's own run of a setting (rates added to the reference's counts)."""
    m = dict(reference()["measured"][key])
    m["success_rate"] = m["success"] / m["episodes"]
    m["collision_rate"] = m["collision"] / m["episodes"]
    return m


def agreement(ours: dict[str, Any], theirs: dict[str, Any]) -> dict[str, bool]:
    """Which figures agree with CrowdNav's.

    Success and collision rates within :data:`RATE_TOLERANCE`, mean navigation time of successes
    within :data:`TIME_TOLERANCE` of CrowdNav's.
    """
    t0 = theirs["mean_nav_time_s"]
    return {
        "success": abs(ours["success_rate"] - theirs["success_rate"]) <= RATE_TOLERANCE,
        "collision": abs(ours["collision_rate"] - theirs["collision_rate"]) <= RATE_TOLERANCE,
        "nav_time": abs(ours["mean_nav_time_s"] - t0) <= TIME_TOLERANCE * t0,
    }


def run_suite(
    planners: Sequence[str] | None = None,
    episodes_per_setting: int = EPISODES,
    seed: int = TEST_SEED,
    policies: Sequence[PolicyRef] = (),
    drives: Sequence[str] = DRIVES,
) -> list[dict[str, Any]]:
    """Every setting of :data:`SETTINGS` with every planner and policy, for each of `drives`.

    Planners default to :data:`PLANNERS` (none when `policies` are given, as ``proxemic eval``
    does). Runs scene seeds ``seed .. seed + episodes_per_setting - 1``: one summary row per
    (setting, drive, planner or policy), with ``setting``, ``drive``, ``planner`` (a policy's name)
    and ``seeds`` added. A policy is built for each drive with that drive's action space.

    Raises:
        InputError: A bad episode count, seed, planner or drive name.
    """
    if isinstance(episodes_per_setting, bool) or not isinstance(episodes_per_setting, int) or episodes_per_setting < 1:
        raise input_error("episodes", "a positive integer", episodes_per_setting)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise input_error("seed", "a non-negative integer", seed)
    chosen = list(planners) if planners else ([] if policies else list(PLANNERS))
    for planner in chosen:
        if planner not in PLANNERS:
            raise input_error("planner", f"one of {list(PLANNERS)}", planner)
    if isinstance(drives, str) or not drives:
        raise input_error("drives", f"a non-empty sequence of names among {list(DRIVES)}", drives)
    settings = [s.with_drive(d) for d in drives for s in SETTINGS]
    seeds = range(seed, seed + episodes_per_setting)
    rows = []
    for setting in settings:
        runs = [(p, episodes(setting, seeds, p)) for p in chosen]
        runs += [(ref.name, policy_episodes(setting, seeds, ref)) for ref in policies]
        for name, records in runs:
            row = summarise(records)
            rows.append(
                {
                    "setting": setting.key,
                    "drive": setting.drive,
                    "planner": name,
                    "seeds": f"{seeds[0]}-{seeds[-1]}",
                    **row,
                }
            )
    return rows


def table_text(rows: Sequence[dict[str, Any]]) -> str:
    """The suite's report as markdown.

    Every planner's and policy's figures per setting and drive, the holonomic robot's below
    CrowdNav's own ORCA robot's (it has no unicycle mode), the agreement of ``astar_orca``
    (CrowdNav's ORCA robot in proxemic) with CrowdNav's run, the literature's figures and the
    remaining setup differences.
    """
    ref = reference()
    groups = [s.with_drive(d) for d in DRIVES for s in SETTINGS]
    labels = {(s.key, s.drive): s.label for s in groups}
    order = {(s.key, s.drive): k for k, s in enumerate(groups)}
    crowdnav_orca = "CrowdNav's ORCA robot (its code)"

    def figures(r: dict[str, Any]) -> list[str]:
        return [
            f"{r['episodes']}",
            f"{r['success_rate']:.3f}",
            f"{r['collision_rate']:.3f}",
            f"{r['timeout'] / r['episodes']:.3f}",
            f"{r['mean_nav_time_s']:.2f}",
            f"{r['discomfort_frequency']:.3f}",
        ]

    body = []
    agree = []
    mark = {True: "ok", False: "DIFFERS"}
    for key in sorted({(r["setting"], r.get("drive", "holonomic")) for r in rows}, key=order.__getitem__):
        holonomic = key[1] == "holonomic"
        theirs = measured(key[0])
        if holonomic:
            body.append([labels[key], crowdnav_orca, *figures(theirs)])
        for r in (r for r in rows if (r["setting"], r.get("drive", "holonomic")) == key):
            body.append([labels[key], r["planner"], *figures(r)])
            if r["planner"] == "astar_orca" and holonomic:
                ok = agreement(r, theirs)
                agree.append(
                    [
                        labels[key],
                        f"{r['success_rate']:.3f} / {theirs['success_rate']:.3f} ({mark[ok['success']]})",
                        f"{r['collision_rate']:.3f} / {theirs['collision_rate']:.3f} ({mark[ok['collision']]})",
                        f"{r['mean_nav_time_s']:.2f} / {theirs['mean_nav_time_s']:.2f} ({mark[ok['nav_time']]})",
                    ]
                )
    head = ["setting", "planner", "episodes", "success", "collision", "timeout", "nav time (s)", "discomfort freq."]
    prov = ref["provenance"]
    lines = [
        "CrowdNav protocol: proxemic's planners beside CrowdNav's own ORCA robot "
        f"(CrowdNav {prov['crowdnav_commit'][:10]}, {prov['episodes_per_setting']} test episodes per setting, "
        f"measured {prov['date']}; its ORCA robot is holonomic only, so the unicycle's settings have no row of "
        "its own); nav time: mean over successes (25 s when none)",
        "",
        markdown.table(head, body),
    ]
    if agree:
        lines += [
            "",
            f"Agreement of astar_orca with CrowdNav's ORCA robot (rates within {RATE_TOLERANCE}, nav time within "
            f"{TIME_TOLERANCE:.0%}):",
            "",
            markdown.table(
                ["setting", "success ours / CrowdNav", "collision ours / CrowdNav", "nav time (s) ours / CrowdNav"],
                agree,
            ),
        ]
    lines += [
        "",
        f"Literature ({ref['literature']['setting']}; {ref['literature']['source']}):",
        "",
        markdown.table(
            ["policy", "success", "collision", "intrusion (%)"],
            [
                [k, f"{v['success']:.2f}", f"{v['collision']:.2f}", f"{v['intrusion_percent']:.2f}"]
                for k, v in ref["literature"]["rows"].items()
            ],
        ),
        "",
        "Remaining setup differences:",
        *[f"- {d}" for d in DIFFERENCES],
    ]
    return "\n".join(lines)


#: The generated block of ``docs/crowdnav.md`` (every planner's figures), between these lines.
DOCS_BEGIN = "<!-- BEGIN GENERATED: python -m proxemic.crowdnav docs/crowdnav.md (do not edit by hand) -->"
#: ... and this one.
DOCS_END = "<!-- END GENERATED -->"


def write_docs(path: Path, episodes_per_setting: int = EPISODES, seed: int = TEST_SEED) -> list[dict[str, Any]]:
    """Runs the suite with every built-in planner and both drives and writes its report into `path`'s generated block.

    Returns the rows. Raises :class:`InputError` when `path` has no block (the two marker lines
    :data:`DOCS_BEGIN` and :data:`DOCS_END`).
    """
    markdown.check_block(path, DOCS_BEGIN, DOCS_END)
    rows = run_suite(None, episodes_per_setting, seed)
    block = (
        f"Every built-in planner, scene seeds {seed}-{seed + episodes_per_setting - 1} of each setting "
        f"(`proxemic eval --suite crowdnav --episodes {episodes_per_setting}` prints the same table):\n\n"
        f"{table_text(rows)}\n"
    )
    markdown.write_block(path, DOCS_BEGIN, DOCS_END, block)
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m proxemic.crowdnav docs/crowdnav.md``: regenerates the docs' table of every planner."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m proxemic.crowdnav", description=main.__doc__)
    parser.add_argument("page", type=Path, help="the docs page with the generated block (docs/crowdnav.md)")
    parser.add_argument("--episodes", type=int, default=EPISODES, help=f"episodes per setting (default {EPISODES})")
    args = parser.parse_args(argv)
    write_docs(args.page, args.episodes)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
