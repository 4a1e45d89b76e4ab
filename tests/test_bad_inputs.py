"""Bad inputs, table-driven: each gets a typed proxemic error (or exit code 2 with a one-line message
naming the field) and never kills the process.

Every case runs in its own subprocess, so a crash (a process exit, an abort, a Rust panic that
escapes) fails the case instead of the test session. A case is
``(id, code, error class, field)``: `code` runs after the preamble below and must raise an error of
`error class` (a name in :mod:`proxemic.errors`) whose ``field`` is `field`. CLI cases are
``(id, argv, field)`` and must exit with code 2, print one line on stderr, and name `field` there.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

PREAMBLE = """
import json, os, sys, tempfile, warnings
import numpy as np
import gymnasium as gym
import proxemic
from proxemic import _core, errors, scenarios
import proxemic.env

def scen(text):
    f = tempfile.NamedTemporaryFile('w', suffix='.toml', delete=False)
    f.write(text)
    f.close()
    return f.name

ROOM = '''
[scene]
name = "room"
bounds = [0, 0, 10, 8]
[[wall]]
from = [0, 0]
to = [10, 0]
[[wall]]
from = [10, 0]
to = [10, 8]
[[wall]]
from = [10, 8]
to = [0, 8]
[[wall]]
from = [0, 8]
to = [0, 0]
'''
ROBOT = '''
[[robot]]
start = [1.5, 4, 0]
goal = [8.5, 4]
'''

def museum(**kw):
    env = gym.make("proxemic/Museum-v5", **kw)
    return env

def stepped(**kw):
    env = museum(**kw)
    env.reset(seed=0)
    return env

def multi(robots=2, reset=True):
    env = proxemic.parallel_env("museum_multi", robots=robots)
    if reset:
        env.reset(seed=0)
    return env

try:
    exec(compile(sys.argv[1], "<case>", "exec"))
except errors.ProxemicError as e:
    print(json.dumps({"class": type(e).__name__, "field": e.field, "message": str(e)}))
except BaseException as e:
    print(json.dumps({"class": "UNTYPED " + type(e).__name__, "field": None, "message": repr(e)}))
else:
    print(json.dumps({"class": "NO ERROR", "field": None, "message": ""}))
"""

S = "scen(ROOM + ROBOT + {extra!r})"

#: (id, code, error class, field)
API_CASES: list[tuple[str, str, str, str | None]] = [
    # --- the single-robot env
    ("env-step-before-reset", "museum().unwrapped.step(np.zeros(3))", "NeedsResetError", None),
    (
        "env-step-after-end",
        "env = stepped()\n"
        "while True:\n    *_, t, u, _ = env.step(np.ones(3))\n    if t or u: break\nenv.step(np.zeros(3))",
        "NeedsResetError",
        None,
    ),
    ("env-action-shape-1x3", "stepped().step(np.zeros((1, 3)))", "InputError", "action"),
    ("env-action-shape-2", "stepped().step(np.zeros(2))", "InputError", "action"),
    ("env-action-complex", "stepped().step(np.zeros(3, dtype=complex))", "InputError", "action"),
    ("env-action-bool", "stepped().step(np.array([True, False, True]))", "InputError", "action"),
    ("env-action-nan", "stepped().step(np.array([np.nan, 0, 0]))", "InputError", "action"),
    ("env-action-inf", "stepped().step(np.array([0, np.inf, 0]))", "InputError", "action"),
    ("env-action-string", "stepped().step('forward')", "InputError", "action"),
    ("env-action-none", "stepped().step(None)", "InputError", "action"),
    ("env-action-dict", "stepped().step({'vx': 1})", "InputError", "action"),
    ("env-seed-true", "museum().reset(seed=True)", "InputError", "seed"),
    ("env-seed-negative", "museum().reset(seed=-1)", "InputError", "seed"),
    ("env-seed-float", "museum().reset(seed=1.5)", "InputError", "seed"),
    ("env-seed-string", "museum().reset(seed='0')", "InputError", "seed"),
    ("env-reset-options", "museum().reset(seed=0, options={'goal': [1, 2]})", "InputError", "options"),
    ("env-width-zero", "museum(render_mode='rgb_array', width=0)", "InputError", "width"),
    ("env-height-negative", "museum(render_mode='topdown', height=-5)", "InputError", "height"),
    ("env-width-float", "museum(width=640.5)", "InputError", "width"),
    ("env-width-string", "museum(width='640')", "InputError", "width"),
    ("env-width-huge", "museum(width=100000)", "InputError", "width"),
    ("env-render-mode", "museum(render_mode='ascii')", "InputError", "render_mode"),
    ("env-camera", "museum(camera='side')", "InputError", "camera"),
    ("env-overlay", "museum(overlays=['heatmap'])", "InputError", "overlays"),
    # --- the parallel env
    ("par-step-before-reset", "multi(reset=False).step({})", "NeedsResetError", None),
    (
        "par-step-after-all-finished",
        "env = multi(2)\nfor _ in range(3000):\n    if not env.agents: break\n"
        "    env.step({a: np.ones(3) for a in env.agents})\nenv.step({})",
        "NeedsResetError",
        None,
    ),
    ("par-unknown-agent", "multi().step({'robot_9': np.zeros(3)})", "InputError", "actions"),
    ("par-missing-agent", "multi().step({'robot_0': np.zeros(3)})", "InputError", "actions"),
    (
        "par-action-bool",
        "multi().step({'robot_0': np.zeros(3), 'robot_1': np.array([True, True, False])})",
        "InputError",
        "actions['robot_1']",
    ),
    (
        "par-action-shape",
        "multi().step({'robot_0': np.zeros((1, 3)), 'robot_1': np.zeros(3)})",
        "InputError",
        "actions['robot_0']",
    ),
    ("par-seed-true", "multi(reset=False).reset(seed=True)", "InputError", "seed"),
    ("par-robots-zero", "proxemic.parallel_env('museum_multi', robots=0)", "ScenarioError", "robots"),
    ("par-robots-many", "proxemic.parallel_env('museum_multi', robots=12)", "ScenarioError", "robots"),
    ("par-robots-float", "proxemic.parallel_env('museum_multi', robots=2.5)", "InputError", "robots"),
    ("par-step-none", "multi().step(None)", "InputError", "actions"),
    ("par-step-list", "multi().step([np.zeros(3), np.zeros(3)])", "InputError", "actions"),
    (
        "par-autopilot-string",
        "proxemic.parallel_env('museum_multi', robots=2, autopilot='robot_0')",
        "InputError",
        "autopilot",
    ),
    ("gen-duplicate-key", "proxemic.env.ProxemicEnv('generated/3?robots=1&robots=2')", "ScenarioError", "robots"),
    (
        "francis-duplicate-key",
        "proxemic.env.ProxemicEnv('francis2023/crossing_90?seed=1&seed=2')",
        "ScenarioError",
        "seed",
    ),
    ("francis-archetype-none", "gym.make('proxemic/Francis2023-v7', archetype=None)", "InputError", "archetype"),
    (
        "sim-crowd-too-large",
        "from proxemic.sim.model import check_crowd_fits, max_people\ncheck_crowd_fits({'persons': [{}] * (max_people(1) + 1), 'robots': [{}]})",
        "InputError",
        "persons",
    ),
    (
        "vec-num-envs-huge",
        "from proxemic.vector import vector_env\nvector_env('museum', num_envs=10**9)",
        "InputError",
        "num_envs",
    ),
    (
        "core-astar-path-negative",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.astar_path(-1)",
        "InputError",
        "robot",
    ),
    (
        "core-reset-seed-2-64",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.reset(2**64, np.zeros(w.stride), np.zeros(w.num_people * _core.PERSON_OUT))",
        "InputError",
        "seed",
    ),
    (
        "video-out-unwritable",
        "from proxemic.viz.video import write_video\nwrite_video([np.zeros((8, 8, 3), np.uint8)], '/proc/proxemic/v.mp4')",
        "InputError",
        "out",
    ),
    ("par-width-zero", "proxemic.parallel_env('museum_multi', robots=2, width=0)", "InputError", "width"),
    ("par-robots-huge", "proxemic.parallel_env('museum_multi', robots=2**70)", "ScenarioError", "robots"),
    ("par-robots-string", "proxemic.parallel_env('museum_multi', robots='2')", "InputError", "robots"),
    (
        "gen-duplicate-key-apart",
        "proxemic.env.ProxemicEnv('generated/3?density=1&robots=1&density=2')",
        "ScenarioError",
        "density",
    ),
    (
        "francis-duplicate-max-time",
        "proxemic.env.ProxemicEnv('francis2023/crossing_90?max_time=9&max_time=30')",
        "ScenarioError",
        "max_time",
    ),
    (
        "core-generate-duplicate-key",
        "_core.generate('francis2023/frontal_approach?max_time=20&seed=1&max_time=30')",
        "ScenarioError",
        "max_time",
    ),
    ("gen-door-too-wide", "_core.generate('generated/2?door_width=3')", "ScenarioError", "door_width"),
    ("francis-archetype-number", "gym.make('proxemic/Francis2023-v7', archetype=3)", "InputError", "archetype"),
    (
        "vec-num-envs-limit-plus-one",
        "from proxemic.vector import vector_env, MAX_NUM_ENVS\nvector_env('museum', num_envs=MAX_NUM_ENVS + 1)",
        "InputError",
        "num_envs",
    ),
    (
        "core-reset-seed-negative",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.reset(-1, np.zeros(w.stride), np.zeros(w.num_people * _core.PERSON_OUT))",
        "InputError",
        "seed",
    ),
    (
        "core-trajectory-huge",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.trajectory(2**64)",
        "InputError",
        "robot",
    ),
    (
        "core-episode-metrics-negative",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.episode_metrics([0, -1])",
        "InputError",
        "robots[1]",
    ),
    (
        "core-with-robot-planner-negative",
        "_core.Scenario.from_file(scenarios.resolve('museum')).with_robot_planner(-1, 'astar')",
        "InputError",
        "robot",
    ),
    (
        "core-with-robots-huge",
        "_core.Scenario.from_file(scenarios.resolve('museum')).with_robots(2**70)",
        "ScenarioError",
        "robots",
    ),
    (
        "core-step-worlds-threads-negative",
        "env = stepped()\nws = env.unwrapped.ws\n_core.step_worlds([ws.world], ws._actions, ws._physics, ws.sim.state, ws.sim.contacts, ws.out, ws.people, threads=-1)",
        "InputError",
        "threads",
    ),
    (
        "policy-raises-at-step",
        "proxemic.evaluate(lambda obs: 1 / 0, scenario='museum', episodes=1, planners=[])",
        "PolicyError",
        "policy",
    ),
    (
        "policy-exits-at-step",
        "proxemic.evaluate(lambda obs: sys.exit(4), scenario='museum', episodes=1, planners=[])",
        "PolicyError",
        "policy",
    ),
    (
        "policy-reset-raises",
        "class P:\n    def __call__(self, obs): return np.zeros(3)\n    def reset(self, seed): raise KeyError(seed)\n"
        "proxemic.evaluate(P(), scenario='museum', episodes=1, planners=[])",
        "PolicyError",
        "policy",
    ),
    (
        "policy-nan-action",
        "proxemic.evaluate(lambda obs: np.array([np.nan, 0, 0]), scenario='museum', episodes=1, planners=[])",
        "InputError",
        "policy",
    ),
    (
        "policy-complex-action",
        "proxemic.evaluate(lambda obs: np.zeros(3, complex), scenario='museum', episodes=1, planners=[])",
        "InputError",
        "policy",
    ),
    (
        "policy-string-action",
        "proxemic.evaluate(lambda obs: 'forward', scenario='museum', episodes=1, planners=[])",
        "InputError",
        "policy",
    ),
    (
        "run-episode-policy-raises",
        "from proxemic.runner import run_episode\nrun_episode('museum', 0, policy=lambda obs: [][1])",
        "PolicyError",
        "policy",
    ),
    (
        "joint-policy-raises",
        "from proxemic.policy import joint_policy\nenv = multi()\nact = joint_policy(lambda obs: 1 / 0, env.possible_agents)\n"
        "act.reset(0)\nact({a: None for a in env.agents})",
        "PolicyError",
        "policy",
    ),
    (
        "joint-policy-sys-exit",
        "from proxemic.policy import joint_policy\nenv = multi()\nact = joint_policy(lambda obs: sys.exit(0), env.possible_agents)\n"
        "act.reset(0)\nact({a: None for a in env.agents})",
        "PolicyError",
        "policy",
    ),
    (
        "video-out-suffix",
        "from proxemic.viz.video import write_video\nwrite_video([np.zeros((8, 8, 3), np.uint8)], tempfile.mkdtemp() + '/v.txt')",
        "InputError",
        "out",
    ),
    (
        "video-record-out-unwritable",
        "from proxemic.viz.video import record_episode\nrecord_episode('museum', path='/proc/proxemic/v.mp4', max_steps=1)",
        "InputError",
        "out",
    ),
    (
        "video-record-width-string",
        "from proxemic.viz.video import record_episode\nrecord_episode('museum', width='640')",
        "InputError",
        "width",
    ),
    ("par-height-string", "proxemic.parallel_env('museum_multi', robots=2, height='480')", "InputError", "height"),
    ("par-autopilot-number", "proxemic.parallel_env('museum_multi', robots=2, autopilot=1)", "InputError", "autopilot"),
    ("env-autopilot-string", "proxemic.ProxemicEnv('museum', autopilot='robot_0')", "InputError", "autopilot"),
    (
        "env-planner-actions-number",
        "proxemic.ProxemicEnv('museum', planner_actions=0)",
        "InputError",
        "planner_actions",
    ),
    ("vec-autopilot-string", "proxemic.vector_env('museum', 2, autopilot='yes')", "InputError", "autopilot"),
    ("par-step-array", "multi().step(np.zeros((2, 3)))", "InputError", "actions"),
    # --- scenario files
    (
        "scn-unknown-field",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\ncolour='red'\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.colour",
    ),
    (
        "scn-bounds-inverted",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[5,5,0,0]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.bounds",
    ),
    (
        "scn-bounds-nan",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,nan,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.bounds",
    ),
    (
        "scn-bounds-huge-grid",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,1000,1000]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.resolution",
    ),
    (
        "scn-bounds-long-side",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,100000,1]\\n[[robot]]\\nstart=[1,0.5,0]\\ngoal=[4,0.5]\"))",
        "ScenarioError",
        "scene.bounds",
    ),
    (
        "scn-resolution-zero",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\nresolution=0\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.resolution",
    ),
    (
        "scn-resolution-fine",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,500,300]\\nresolution=0.01\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.resolution",
    ),
    (
        "scn-start-time",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\nstart_time='25:99'\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.start_time",
    ),
    (
        "scn-physics-not-multiple",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\ncontrol_hz=10\\nphysics_hz=15\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.physics_hz",
    ),
    (
        "scn-control-hz-negative",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\ncontrol_hz=-10\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.control_hz",
    ),
    (
        "scn-empty-name",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname=' '\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "scene.name",
    ),
    (
        "scn-no-robot",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\"))",
        "ScenarioError",
        "robot",
    ),
    (
        "scn-robot-goal-outside",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[40,4]\"))",
        "ScenarioError",
        "robot[0].goal",
    ),
    (
        "scn-robot-start-string",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart='here'\\ngoal=[4,4]\"))",
        "ScenarioError",
        "robot[0].start",
    ),
    (
        "scn-robot-planner",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\nplanner='rrt'\"))",
        "ScenarioError",
        "robot[0].planner",
    ),
    (
        "scn-robots-overlap",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[robot]]\\nstart=[1.1,1,0]\\ngoal=[4,1]\"))",
        "ScenarioError",
        None,
    ),
    (
        "scn-robot-speed-negative",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\nmax_speed=-1\"))",
        "ScenarioError",
        "robot[0].max_speed",
    ),
    (
        "scn-robot-radius-zero",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\nradius=0\"))",
        "ScenarioError",
        "robot[0].radius",
    ),
    (
        "scn-walker-one-point",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[person]]\\nroute=[[2,2]]\"))",
        "ScenarioError",
        "person[0].route",
    ),
    (
        "scn-standing-no-pose",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[person]]\\nbehaviour='standing'\"))",
        "ScenarioError",
        "person[0].pose",
    ),
    (
        "scn-behaviour-unknown",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[person]]\\nbehaviour='dancer'\\npose=[2,2,0]\"))",
        "ScenarioError",
        "person[0].behaviour",
    ),
    (
        "scn-person-speed-preset",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[person]]\\nroute=[[1,3],[4,3]]\\nspeed='warp'\"))",
        "ScenarioError",
        "person[0].speed",
    ),
    (
        "scn-person-speed-negative",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[person]]\\nroute=[[1,3],[4,3]]\\nspeed=-1\"))",
        "ScenarioError",
        "person[0].speed",
    ),
    (
        "scn-object-kind",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[object]]\\nname='o'\\nkind='piano'\\npose=[2,4,0]\\nsize=[1,1]\"))",
        "ScenarioError",
        "object[0].kind",
    ),
    (
        "scn-object-no-size",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[object]]\\nname='o'\\nkind='table'\\npose=[2,4,0]\"))",
        "ScenarioError",
        "object[0].size",
    ),
    (
        "scn-object-duplicate-name",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[object]]\\nname='o'\\nkind='table'\\npose=[2,4,0]\\nsize=[0.5,0.5]\\n[[object]]\\nname='o'\\nkind='table'\\npose=[3,4,0]\\nsize=[0.5,0.5]\"))",
        "ScenarioError",
        None,
    ),
    (
        "scn-activity-unknown-object",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[[activity]]\\nobject='ghost'\\nstart='10:00'\\nend='11:00'\"))",
        "ScenarioError",
        None,
    ),
    ("scn-toml-syntax", "proxemic.env.ProxemicEnv(scen(\"[scene\\nname='x'\"))", "ScenarioError", None),
    (
        "scn-wall-nan",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[wall]]\\nfrom=[0,nan]\\nto=[5,0]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "wall[0].from",
    ),
    (
        "scn-episode-max-time",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[episode]\\nmax_time=-5\"))",
        "ScenarioError",
        "episode.max_time",
    ),
    (
        "scn-sensors-rays",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[sensors]\\nlidar_rays=0\"))",
        "ScenarioError",
        "sensors.lidar_rays",
    ),
    (
        "scn-proxemics-preset",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[proxemics]\\nzones='martian'\"))",
        "ScenarioError",
        "proxemics.zones",
    ),
    (
        "scn-reward-nan",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\\n[reward]\\nsuccess=nan\"))",
        "ScenarioError",
        "reward.success",
    ),
    (
        "scn-goal-in-wall",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[wall]]\\nfrom=[4,0]\\nto=[4,5]\\nthickness=1\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        None,
    ),
    ("core-scenario-missing-file", "_core.Scenario.from_file('/nonexistent/x.toml')", "ScenarioError", None),
    (
        "core-with-robots-zero",
        "_core.Scenario.from_file(scenarios.resolve('museum_multi')).with_robots(0)",
        "ScenarioError",
        None,
    ),
    (
        "core-with-robots-many",
        "_core.Scenario.from_file(scenarios.resolve('museum_multi')).with_robots(99)",
        "ScenarioError",
        None,
    ),
    (
        "core-with-planner",
        "_core.Scenario.from_file(scenarios.resolve('museum')).with_planner('rrt')",
        "ScenarioError",
        None,
    ),
    (
        "core-with-goal-outside",
        "_core.Scenario.from_file(scenarios.resolve('museum')).with_goal((1000, 1000))",
        "ScenarioError",
        None,
    ),
    (
        "core-with-start-time",
        "_core.Scenario.from_file(scenarios.resolve('museum')).with_start_time('26:00')",
        "InputError",
        None,
    ),
    (
        "core-replans-robot",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.replans(99)",
        "InputError",
        "robot",
    ),
    (
        "core-path-robot",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.path(5)",
        "InputError",
        "robot",
    ),
    (
        "core-reset-short-buffer",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.reset(0, np.zeros(3), np.zeros(3))",
        "InputError",
        None,
    ),
    (
        "core-reset-float32-buffer",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.reset(0, np.zeros(w.stride, np.float32), np.zeros(w.num_people * _core.PERSON_OUT))",
        "InputError",
        "out",
    ),
    (
        "core-reset-list-buffer",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.reset(0, [0.0] * w.stride, np.zeros(w.num_people * _core.PERSON_OUT))",
        "InputError",
        "out",
    ),
    (
        "core-step-float32-state",
        "env = stepped()\nws = env.unwrapped.ws\nws.world.step(ws._actions, ws._physics, ws.sim.state.astype(np.float32), ws.sim.contacts, ws.out, ws.people)",
        "InputError",
        "state",
    ),
    (
        "core-step-2d-actions",
        "env = stepped()\nws = env.unwrapped.ws\nws.world.step(np.zeros((1, 3)), ws._physics, ws.sim.state, ws.sim.contacts, ws.out, ws.people)",
        "InputError",
        "actions",
    ),
    (
        "core-step-strided-state",
        "env = stepped()\nws = env.unwrapped.ws\nws.world.step(ws._actions, ws._physics, np.zeros(2 * ws.sim.state.size)[::2], ws.sim.contacts, ws.out, ws.people)",
        "InputError",
        "state",
    ),
    (
        "core-step-worlds-uint8-contacts-as-float",
        "env = stepped()\nws = env.unwrapped.ws\n_core.step_worlds([ws.world], ws._actions, ws._physics, ws.sim.state, ws.sim.contacts.astype(np.float64), ws.out, ws.people)",
        "InputError",
        "contacts",
    ),
    ("core-parse-time", "_core.parse_time_of_day('ten past')", "InputError", "time_of_day"),
    (
        "core-set-planning-length",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.set_planning([True, False, True])",
        "InputError",
        None,
    ),
    (
        "core-step-before-reset",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.step(np.full(3, np.nan), lambda: None, np.zeros(6), np.zeros(1, np.uint8), np.zeros(w.stride), np.zeros(w.num_people * _core.PERSON_OUT))",
        "InputError",
        None,
    ),
    ("api-unknown-scenario", "proxemic.env.ProxemicEnv('musuem')", "UnknownNameError", None),
    ("api-unknown-env-id", "gym.make('proxemic/Musem-v4')", "UNTYPED NameNotFound", None),
    ("api-planner-unknown", "museum(planner='rrt')", "ScenarioError", None),
    ("api-goal-outside", "museum(goal=(1000, 1000))", "ScenarioError", None),
    ("api-eband-unknown", "museum(planner='eband', eband={'spring': 1.0})", "ScenarioError", None),
    (
        "core-plan-nan-start",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.plan(0, (float('nan'), 1.0), (5.0, 5.0), False)",
        "InputError",
        "start",
    ),
    (
        "core-plan-inf-goal",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.plan(0, (2.0, 2.0), (float('inf'), 5.0), True)",
        "InputError",
        "goal",
    ),
    (
        "core-plan-nan-time",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.plan(0, (2.0, 2.0), (5.0, 5.0), True, float('nan'))",
        "InputError",
        "time_of_day",
    ),
    (
        "core-layers-time",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('museum')))\nw.social_layers(0, 90000.0)",
        "InputError",
        "time_of_day",
    ),
    (
        "core-object-costs-nan",
        "w = _core.World(_core.Scenario.from_file(scenarios.resolve('care_center')))\nw.object_costs(float('nan'))",
        "InputError",
        "time_of_day",
    ),
    ("api-goal-one-number", "museum(goal=[1.0])", "InputError", "goal"),
    ("api-goal-string", "museum(goal='here')", "InputError", "goal"),
    ("api-goal-nan", "museum(goal=[float('nan'), 1.0])", "ScenarioError", None),
    ("api-eband-list", "museum(planner='eband', eband=[1, 2])", "InputError", "eband"),
    (
        "api-eband-string-value",
        "museum(planner='eband', eband={'contraction_gain': 'high'})",
        "InputError",
        "eband.contraction_gain",
    ),
    (
        "api-eband-nan",
        "museum(planner='eband', eband={'contraction_gain': float('nan')})",
        "ScenarioError",
        "eband.contraction_gain",
    ),
    (
        "video-out-directory",
        "from proxemic.viz.video import write_video\nwrite_video([np.zeros((8, 8, 3), np.uint8)], tempfile.mkdtemp())",
        "InputError",
        "out",
    ),
    (
        "scn-wall-far-outside",
        "proxemic.env.ProxemicEnv(scen(\"[scene]\\nname='x'\\nbounds=[0,0,5,5]\\n[[wall]]\\nfrom=[-9223372036854775808,0]\\nto=[5,0]\\n[[robot]]\\nstart=[1,1,0]\\ngoal=[4,4]\"))",
        "ScenarioError",
        "wall[0].from",
    ),
    (
        "scn-start-is-goal",
        "proxemic.env.ProxemicEnv(scen(ROOM + '[[robot]]\\nstart = [1.5, 4, 0]\\ngoal = [1.6, 4]'))",
        "ScenarioError",
        "robot[0].goal",
    ),
    (
        "scn-person-on-start",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + '[[person]]\\nbehaviour = \"standing\"\\npose = [1.6, 4, 0]'))",
        "ScenarioError",
        "person[0].pose",
    ),
    (
        "scn-people-same-pose",
        'proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + \'[[person]]\\nbehaviour = "standing"\\npose = [5, 5, 0]\\n[[person]]\\nbehaviour = "standing"\\npose = [5, 5, 1]\'))',
        "ScenarioError",
        "person[1].pose",
    ),
    (
        "scn-jitter-outside",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + '[episode.randomize]\\nrobot_start_jitter = 2.0'))",
        "ScenarioError",
        "episode.randomize.robot_start_jitter",
    ),
    (
        "scn-control-rate-slow",
        "proxemic.env.ProxemicEnv(scen(ROOM.replace('bounds = [0, 0, 10, 8]', 'bounds = [0, 0, 10, 8]\\ncontrol_hz = 1\\nphysics_hz = 100') + ROBOT))",
        "ScenarioError",
        "scene.control_hz",
    ),
    (
        "scn-physics-rate-slow",
        "proxemic.env.ProxemicEnv(scen(ROOM.replace('bounds = [0, 0, 10, 8]', 'bounds = [0, 0, 10, 8]\\ncontrol_hz = 10\\nphysics_hz = 10') + ROBOT))",
        "ScenarioError",
        "scene.physics_hz",
    ),
    (
        "scn-painting-faces-wall",
        'proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + \'[[object]]\\nname = "p"\\nkind = "painting"\\npose = [5, 7.9, 1.5707963267948966]\\nsize = [0.1, 1.5]\\ninteraction = { shape = "trapezoid", length = 2.0, near_width = 1.5, far_width = 3.0 }\'))',
        "ScenarioError",
        "object[0].pose",
    ),
    (
        "scn-polygon-bowtie",
        'proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + \'[[object]]\\nname = "t"\\nkind = "table"\\npose = [5, 2, 0]\\nsize = [0.5, 0.5]\\ninteraction = { shape = "polygon", points = [[4, 1], [7, 3], [7, 1], [4, 2]] }\'))',
        "ScenarioError",
        "object[0].interaction.points",
    ),
    (
        "scn-polygon-spike",
        'proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + \'[[object]]\\nname = "t"\\nkind = "table"\\npose = [5, 2, 0]\\nsize = [0.5, 0.5]\\ninteraction = { shape = "polygon", points = [[4, 1], [6, 1], [6, 3], [6, 1.5], [4, 3]] }\'))',
        "ScenarioError",
        "object[0].interaction.points",
    ),
    (
        "scn-wall-three-numbers",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + '[[wall]]\\nfrom = [2, 2]\\nto = [8, 0, 1]'))",
        "ScenarioError",
        "wall[4].to",
    ),
    (
        "scn-robot-start-two-numbers",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT.replace('start = [1.5, 4, 0]', 'start = [1.5, 4]')))",
        "ScenarioError",
        "robot[0].start",
    ),
    (
        "scn-bounds-five-numbers",
        "proxemic.env.ProxemicEnv(scen(ROOM.replace('bounds = [0, 0, 10, 8]', 'bounds = [0, 0, 10, 8, 9]') + ROBOT))",
        "ScenarioError",
        "scene.bounds",
    ),
    (
        "scn-route-point-three-numbers",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + '[[person]]\\nroute = [[2, 2], [5, 5, 1]]'))",
        "ScenarioError",
        "person[0].route",
    ),
    (
        "scn-interaction-a-string",
        'proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + \'[[object]]\\nname = "t"\\nkind = "table"\\npose = [5, 2, 0]\\nsize = [0.5, 0.5]\\ninteraction = "circle"\'))',
        "ScenarioError",
        "object[0].interaction",
    ),
    (
        "scn-interaction-without-shape",
        'proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + \'[[object]]\\nname = "t"\\nkind = "table"\\npose = [5, 2, 0]\\nsize = [0.5, 0.5]\\ninteraction = { radius = 1 }\'))',
        "ScenarioError",
        "object[0].interaction",
    ),
    (
        "scn-object-kind-a-number",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + '[[object]]\\nname = \"t\"\\nkind = 3\\npose = [5, 2, 0]'))",
        "ScenarioError",
        "object[0].kind",
    ),
    (
        "scn-randomize-a-number",
        "proxemic.env.ProxemicEnv(scen(ROOM + ROBOT + '[episode]\\nrandomize = 3'))",
        "ScenarioError",
        "episode.randomize",
    ),
]

#: (id, argv of ``python -m proxemic.cli``, the field the message names)
CLI_CASES: list[tuple[str, list[str], str]] = [
    ("cli-eval-unknown-planner", ["eval", "--planner", "rrt", "--episodes", "1", "--out", "/tmp/bad-cli"], "planner"),
    (
        "cli-eval-unknown-scenario",
        ["eval", "--scenario", "musuem", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "scenario",
    ),
    ("cli-eval-episodes-zero", ["eval", "--episodes", "0", "--out", "/tmp/bad-cli"], "episodes"),
    ("cli-eval-episodes-text", ["eval", "--episodes", "many", "--out", "/tmp/bad-cli"], "episodes"),
    (
        "cli-eval-policy-missing-module",
        ["eval", "--policy", "no_such_module:make", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    (
        "cli-eval-policy-no-colon",
        ["eval", "--policy", "examples.my_policy", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    ("cli-eval-backend", ["eval", "--backend", "dask", "--episodes", "1", "--out", "/tmp/bad-cli"], "backend"),
    ("cli-eval-overlay", ["eval", "--overlay", "heat", "--episodes", "1", "--out", "/tmp/bad-cli"], "overlay"),
    ("cli-video-unknown-planner", ["video", "--planner", "rrt", "--out", "/tmp/bad-cli/v.mp4"], "planner"),
    ("cli-tune-unknown-scenario", ["tune", "--scenario", "musuem"], "scenario"),
    ("cli-reproduce-unknown-paper", ["reproduce", "smith2020"], "paper"),
    ("cli-unknown-command", ["fly"], "command"),
    ("cli-eval-workers-zero", ["eval", "--workers", "0", "--out", "/tmp/bad-cli"], "--workers"),
    ("cli-eval-workers-negative", ["eval", "--workers", "-3", "--out", "/tmp/bad-cli"], "--workers"),
    ("cli-tune-penalty-nan", ["tune", "--failure-penalty", "nan"], "--failure-penalty"),
    ("cli-tune-penalty-inf", ["tune", "--failure-penalty", "inf"], "--failure-penalty"),
    ("cli-tune-trials-zero", ["tune", "--trials", "0"], "--trials"),
    ("cli-demo-episodes-zero", ["demo", "--episodes", "0"], "--episodes"),
    ("cli-video-out-directory", ["video", "--max-steps", "2", "--out", "/tmp"], "out"),
    ("cli-video-out-unwritable", ["video", "--max-steps", "2", "--out", "/proc/proxemic/v.mp4"], "--out"),
    ("cli-video-out-suffix", ["video", "--max-steps", "2", "--out", "/tmp/bad-cli/v.txt"], "--out"),
    (
        "cli-eval-archetype-without-suite",
        ["eval", "--archetype", "crossing_90", "--out", "/tmp/bad-cli"],
        "--archetype",
    ),
    (
        "cli-eval-scenario-with-suite",
        ["eval", "--suite", "francis2023", "--scenario", "museum", "--out", "/tmp/bad-cli"],
        "--scenario",
    ),
    (
        "cli-eval-policy-complex-action",
        ["eval", "--policy", "tests/bad_policies.py:complex_action", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    (
        "cli-eval-policy-bool-action",
        ["eval", "--policy", "tests/bad_policies.py:bool_action", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    (
        "cli-eval-policy-raises-at-import",
        ["eval", "--policy", "tests/bad_policy_import.py:make", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    (
        "cli-eval-policy-raises-in-factory",
        ["eval", "--policy", "tests/bad_policies.py:raises_in_factory", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    (
        "cli-eval-policy-raises-at-step",
        ["eval", "--policy", "tests/bad_policies.py:raises_at_step", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
    (
        "cli-eval-policy-sys-exit",
        ["eval", "--policy", "tests/bad_policies.py:exits_at_step", "--episodes", "1", "--out", "/tmp/bad-cli"],
        "policy",
    ),
]


def run_case(code: str) -> dict[str, object]:
    result = subprocess.run(
        [sys.executable, "-c", PREAMBLE, textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, f"process died ({result.returncode}): {result.stderr[-2000:]}"
    lines = [line for line in result.stdout.splitlines() if line.startswith("{")]
    assert lines, f"no result line: {result.stdout[-1000:]} {result.stderr[-1000:]}"
    out: dict[str, object] = json.loads(lines[-1])
    return out


#: Cases whose message must also say what arrived (or where) in these words: the weak messages
#: reported before (a string reported as its first letter or as a bare number, a pipe error instead
#: of the path) and the inputs that failed untyped before.
MESSAGES: dict[str, str] = {
    "par-autopilot-string": "got str 'robot_0' (for one agent write autopilot=['robot_0'])",
    "env-width-string": "got str '640'",
    "video-record-width-string": "got str '640'",
    "par-height-string": "got str '480'",
    "par-robots-string": "in [1, 11], got str '2'",
    "par-step-none": "got NoneType None",
    "par-step-list": "got list [array(",
    "gen-duplicate-key": 'robots: expected each parameter at most once, got "robots" twice',
    "gen-duplicate-key-apart": 'got "density" twice',
    "francis-duplicate-key": 'seed: expected each parameter at most once, got "seed" twice',
    "francis-duplicate-max-time": 'got "max_time" twice',
    "francis-archetype-none": "got NoneType None",
    "gen-door-too-wide": "a door width that fits the wall between two rooms of 4.09 m",
    "vec-num-envs-huge": "num_envs: expected an integer from 1 to 1024, got 1000000000",
    "core-astar-path-negative": "got -1",
    "core-reset-seed-2-64": "seed: expected an integer in [0, 2**64), got 18446744073709551616",
    "core-with-robots-huge": "got 1180591620717411303424",
    "video-out-unwritable": "got '/proc/proxemic/v.mp4'",
    "video-out-suffix": "a .txt suffix",
    "policy-raises-at-step": "policy '<lambda>' raised ZeroDivisionError: division by zero at step 0 of the episode of seed 0 on museum",
    "policy-exits-at-step": "policy '<lambda>' called sys.exit(4) at step 0 of the episode of seed 0 on museum",
    "policy-reset-raises": "policy 'P' raised KeyError: 0 in reset(0)",
    "policy-nan-action": "got [nan, 0.0, 0.0] (returned by policy '<lambda>' at step 0 of the episode of seed 0 on museum)",
    "policy-complex-action": "got shape (3,) of complex128 (returned by policy '<lambda>' at step 0",
    "policy-string-action": "got str 'forward'",
    "run-episode-policy-raises": "raised IndexError: list index out of range at step 0 of the episode of seed 0 on museum",
    "joint-policy-raises": "policy 'robot_0' raised ZeroDivisionError: division by zero at step 0 of the episode of seed 0",
    "joint-policy-sys-exit": "policy 'robot_0' called sys.exit(0) at step 0",
}


@pytest.mark.parametrize(("case", "code", "cls", "field"), API_CASES, ids=[c[0] for c in API_CASES])
def test_api_bad_input(case: str, code: str, cls: str, field: str | None) -> None:
    out = run_case(code)
    assert out["class"] == cls, out
    if field is not None:  # file errors append the TOML position: "robot[0].start (line 5, column 7)"
        assert out["field"] == field or str(out["field"]).startswith(field + " (line "), out
    assert out["message"], out
    if case in MESSAGES:
        assert MESSAGES[case] in str(out["message"]), out


@pytest.mark.parametrize(("argv", "field"), [c[1:] for c in CLI_CASES], ids=[c[0] for c in CLI_CASES])
def test_cli_bad_input(argv: list[str], field: str) -> None:
    result = subprocess.run([sys.executable, "-m", "proxemic.cli", *argv], capture_output=True, text=True, timeout=600)
    assert result.returncode == 2, (result.returncode, result.stderr[-2000:])
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    assert field in lines[0], lines[0]


def test_cli_video_out_names_the_flag_and_the_path() -> None:
    """Not ffmpeg's ``[Errno 32] Broken pipe``: the message names ``--out`` and the path, before the episode runs."""
    argv = ["video", "--out", "/proc/proxemic/v.mp4"]
    result = subprocess.run([sys.executable, "-m", "proxemic.cli", *argv], capture_output=True, text=True, timeout=600)
    assert result.returncode == 2, result.stderr
    assert result.stderr.startswith("proxemic: error: --out: expected the path of a video file"), result.stderr
    assert "got '/proc/proxemic/v.mp4'" in result.stderr and "Broken pipe" not in result.stderr, result.stderr


def test_the_table_is_large_and_ids_are_unique() -> None:
    ids = [c[0] for c in API_CASES] + [c[0] for c in CLI_CASES]
    assert len(ids) == len(set(ids))
    assert set(MESSAGES) <= set(ids), set(MESSAGES) - set(ids)
    assert len(ids) >= 100, len(ids)
