"""A gymnasium vector env of N worlds of one scenario, stepped in one call into the core.

:func:`vector_env` returns a :class:`ProxemicVectorEnv`: the same episodes as
``gymnasium.make_vec(env_id, num_envs=N, vectorization_mode="sync")`` (world k reset with seed
``seed + k`` is the plain env reset with that seed; autoreset on the step after an episode ends,
gymnasium's ``NEXT_STEP`` mode), but a vector step is one call into the Rust core
(``proxemic._core.step_worlds``): it turns the N worlds' actions into commands, calls back the
MuJoCo physics of every world (Python, one world after the other), then moves the people and
computes the metrics, rewards, observations and planners of the N worlds. The outputs land in
one float64 buffer of N rows, from which the batched observations, rewards, flags and infos are
sliced without a per-world Python loop.

With ``threads=T`` the worlds are split into T groups of consecutive worlds, each stepped by one
such call on its own thread (the calling thread and T - 1 kept threads). The core runs without
the GIL and MuJoCo's ``mj_step`` releases it, so the groups' MuJoCo stepping and core steps run
in parallel while one group at a time runs the Python parts of its physics. Each world is stepped
by one thread with its own buffers, so the episodes are those of one thread, bit for bit
(``benches/vector_bench.py`` measures both against one env and the sync vector env).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from proxemic import _core, scenarios
from proxemic.errors import REAL_KINDS, InvariantError, NeedsResetError, input_error, invariant_in
from proxemic.records import EpisodeMetrics
from proxemic.sim import timer_off
from proxemic.world import PLANNER_MODES, REWARD_KEYS, WorldSim, action_space, check_flags, check_reset_args

__all__ = ["MAX_NUM_ENVS", "ProxemicVectorEnv", "vector_env"]

#: The most worlds one vector env holds. Each world keeps its own MuJoCo model and data (a few MB
#: for the bundled scenes, more for large crowds) and its core world; 1024 of them already take
#: gigabytes. A larger `num_envs` is refused with an InputError before anything is allocated.
MAX_NUM_ENVS = 1024


class ProxemicVectorEnv(gym.vector.VectorEnv[dict[str, Any], np.ndarray, np.ndarray]):
    """N worlds of one scenario as a ``gymnasium.vector.VectorEnv`` stepped in one core call.

    Each world is a :class:`proxemic.env.ProxemicEnv` (the scenario's first robot acts; other
    robots keep their built-in planners) with the same spaces, rewards, infos and episode end.
    Spaces: ``single_observation_space`` / ``single_action_space`` are the plain env's,
    ``observation_space`` / ``action_space`` their batches (a leading axis of ``num_envs``).

    Autoreset (gymnasium 1.x ``NEXT_STEP``): the step after world k's episode ended resets it
    instead of stepping it (its action is ignored; reward 0, not terminated or truncated, the
    new episode's first observation). ``info["metrics"]`` holds an ended episode's metrics (with
    the mask ``info["_metrics"]``), as in gymnasium's sync vector env.

    Seeding: ``reset(seed=s)`` resets world k with seed ``s + k`` (a list gives one seed per
    world; None continues each world's random stream), so world k's episodes are those of a plain
    env reset with that seed, bit for bit; later autoresets continue the world's stream, as the
    sync vector env's do.

    Rendering is not supported (``render_mode`` None); use the plain env for videos.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}  # noqa: RUF012

    def __init__(
        self,
        scenario: str | Path | _core.Scenario = "museum",
        num_envs: int = 2,
        *,
        autopilot: bool = False,
        planner_actions: bool = True,
        planner: str | None = None,
        eband: Mapping[str, float] | None = None,
        goal: Sequence[float] | None = None,
        subgoal: float | None = None,
        threads: int = 1,
    ) -> None:
        """Builds `num_envs` worlds of `scenario`.

        Args:
            scenario: Bundled scenario name, env id, path to a scenario TOML file, or a
                ``proxemic._core.Scenario``.
            num_envs: Number of worlds, from 1 to :data:`MAX_NUM_ENVS`.
            autopilot: Ignore actions and let the robots' built-in planners drive.
            planner_actions: Run the built-in planner every step for ``info["planner_action"]``
                even while the actions drive (``False`` skips that work).
            planner: Replace the scenario's planner (one of ``proxemic.PLANNERS``).
            eband: Elastic-band gains by name.
            goal: The robot's goal (x, y) in metres instead of the scenario's.
            subgoal: The ``[sensors] subgoal`` look-ahead in metres instead of the scenario's
                (the ``subgoal`` observation key, see :class:`proxemic.env.ProxemicEnv`).
            threads: Threads stepping the worlds, each a group of consecutive worlds (physics
                and core; at most `num_envs` are used). The default, 1, steps the worlds one
                after the other on the calling thread; ``os.cpu_count()`` uses free cores
                (``benches/vector_bench.py``; on a machine whose cores are busy with other work
                more threads only add their switching). Results are the same for any count.

        Raises:
            InputError: A bad `num_envs` or `threads`; ScenarioError / UnknownNameError for a bad
                scenario, planner or gains.
        """
        super().__init__()
        if (
            isinstance(num_envs, bool)
            or not isinstance(num_envs, (int, np.integer))
            or not 1 <= num_envs <= MAX_NUM_ENVS
        ):
            raise input_error("num_envs", f"an integer from 1 to {MAX_NUM_ENVS}", num_envs)
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1:
            raise input_error("threads", "an integer of at least 1", threads)
        check_flags(autopilot=autopilot, planner_actions=planner_actions)
        self.num_envs = int(num_envs)
        self.threads = min(int(threads), self.num_envs)
        self.autopilot = autopilot
        self.render_mode = None
        core, desc = scenarios.load(scenario, planner=planner, eband=eband, goal=goal, subgoal=subgoal)
        self.scenario = desc
        probe = _core.World(core)
        self._robots, self._stride = probe.num_robots, probe.stride
        n, width = self.num_envs, probe.num_robots * probe.stride
        self._out = np.zeros((n, width))
        self._people = np.zeros((n, probe.num_people * _core.PERSON_OUT))
        self._actions = np.full((n, 3 * probe.num_robots), np.nan)
        self._state = np.zeros((n, 6 * probe.num_robots))
        self._contacts = np.zeros((n, probe.num_robots), dtype=np.uint8)
        del probe
        self.sims = [WorldSim(core, desc, (self._out[k], self._people[k])) for k in range(n)]
        if not (autopilot or planner_actions):
            for ws in self.sims:
                ws.set_planning([False] + [True] * (ws.num_robots - 1))
        self._planning = bool(self.sims[0].planning[0])
        self.metadata = {
            **self.metadata,
            "render_fps": round(desc["scene"]["control_hz"]),
        }
        self.single_observation_space = self.sims[0].observation_space(robots=False)
        self.single_action_space = action_space(desc["robots"][0].get("drive", "holonomic"))
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        lay = self.sims[0].layout
        self._layout = lay
        self._reward_col = lay["reward"][0]
        self._flag_col = lay["flags"][0]
        self._info_cols = self.sims[0]._info_cols
        self._rngs: list[np.random.Generator | None] = [None] * n
        # Per world: the seed given to its last reset() and the autoresets since (error messages).
        self._seeds: list[tuple[int | None, int]] = [(None, 0)] * n
        self._autoreset = np.zeros(n, dtype=bool)
        self._started = False
        self._all = list(range(n))
        # The threads of the other groups of worlds (threads > 1), started at the first step.
        self._pool: ThreadPoolExecutor | None = None

    # ------------------------------------------------------------------ gymnasium API
    def reset(
        self, *, seed: int | Sequence[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Resets the worlds (all, or those of ``options["reset_mask"]``).

        Args:
            seed: None (each world continues its random stream), an integer s (world k gets
                s + k) or one seed (or None) per world.
            options: None, or ``{"reset_mask": mask}`` with a (num_envs,) bool array choosing
                the worlds to reset.

        Raises:
            InputError: A bad seed, seed list length, option or mask.
        """
        n = self.num_envs
        opts = dict(options or {})
        mask = opts.pop("reset_mask", None)
        if mask is not None:
            mask = np.asarray(mask)
            if mask.shape != (n,) or mask.dtype != np.bool_ or not mask.any():
                raise input_error("options.reset_mask", f"a bool array of shape ({n},) with a True value", mask)
        if seed is None or (isinstance(seed, (int, np.integer)) and not isinstance(seed, bool)):
            seeds: list[Any] = [None] * n if seed is None else [int(seed) + k for k in range(n)]
        elif isinstance(seed, Sequence) and len(seed) == n:
            seeds = list(seed)
        else:
            raise input_error("seed", f"None, an integer >= 0 or a list of {n} seeds", seed)
        for s in seeds:
            check_reset_args(s, opts)
        chosen = self._all if mask is None else [k for k in range(n) if mask[k]]
        for k in chosen:
            self._reset_world(k, seeds[k])
            self._seeds[k] = (seeds[k], 0)
            self._autoreset[k] = False
        self._started = True
        return self._observations(), self._infos(chosen, [])

    def step(self, actions: Any) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """One control step of every world (worlds whose episode ended last step are reset instead).

        Raises:
            InputError: Actions that are not a (num_envs, 3) array of finite real numbers.
            NeedsResetError: Before the first ``reset()``.
        """
        if not self._started:
            raise NeedsResetError("step() before reset(): call reset() first")
        n = self.num_envs
        if not self.autopilot:
            a = _check_actions(actions, n)
            self._actions[:, :3] = a
        if self._autoreset.any():
            resetting: list[int] = np.flatnonzero(self._autoreset).tolist()
            stepping: list[int] = np.flatnonzero(~self._autoreset).tolist()
        else:
            resetting, stepping = [], self._all
        for k in resetting:
            self._reset_world(k, None)
            self._seeds[k] = (self._seeds[k][0], self._seeds[k][1] + 1)
        if stepping:
            self._step_worlds(stepping)
        out = self._out
        rewards = out[:, self._reward_col].copy()
        terminated = out[:, self._flag_col] != 0.0
        truncated = out[:, self._flag_col + 1] != 0.0
        if resetting:
            rewards[resetting] = 0.0
            terminated[resetting] = False
            truncated[resetting] = False
        done = terminated | truncated
        ended: list[int] = np.flatnonzero(done).tolist()  # resetting worlds are not done
        self._autoreset[:] = done
        return self._observations(), rewards, terminated, truncated, self._infos(self._all, ended)

    def close_extras(self, **kwargs: Any) -> None:
        """Releases the worlds' rendering resources and the stepping threads."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
        for ws in self.sims:
            ws.close()

    # ------------------------------------------------------------------ internals
    def _reset_world(self, k: int, seed: int | None) -> None:
        """Resets world k as ``ProxemicEnv.reset(seed=seed)`` would (the same core seed)."""
        if seed is not None or self._rngs[k] is None:
            self._rngs[k], _ = seeding.np_random(seed)
        rng = self._rngs[k]
        assert rng is not None
        self.sims[k].reset(int(rng.integers(0, 2**63 - 1)))

    def _step_worlds(self, idx: list[int]) -> None:
        """Steps the worlds `idx`: in one core call, or in `threads` groups on as many threads.

        Each group is one ``_core.step_worlds`` call (its worlds' commands, their physics called
        back one by one, then their people, metrics and observations). The core runs without the
        GIL and MuJoCo's ``mj_step`` releases it too, so while one thread runs the Python parts of
        its group's physics the others step MuJoCo or the core. MuJoCo's timer callback is
        switched off once around all of it (``proxemic.sim.timer``: a process-wide setting the
        threads must not toggle each on its own).
        """
        groups = min(self.threads, len(idx))
        with timer_off():
            if groups == 1:
                self._step_group(idx)
                return
            size, extra = divmod(len(idx), groups)
            parts, start = [], 0
            for g in range(groups):
                stop = start + size + (g < extra)
                parts.append(idx[start:stop])
                start = stop
            if self._pool is None:
                self._pool = ThreadPoolExecutor(max_workers=self.threads - 1, thread_name_prefix="proxemic-vector")
            futures = [self._pool.submit(self._step_group, part) for part in parts[1:]]
            errors: list[BaseException] = []
            try:
                self._step_group(parts[0])
            except BaseException as e:  # the other groups are still waited for
                errors.append(e)
            for f in futures:
                if (failed := f.exception()) is not None:
                    errors.append(failed)
            if errors:
                raise errors[0]

    def _step_group(self, idx: list[int]) -> None:
        """Steps the worlds `idx` in one core call (their physics called back one by one).

        A run of consecutive worlds is stepped on views of the batch buffers' rows; any other
        set (some worlds are being reset) on copies of its rows, written back after.
        """
        sims = self.sims
        lo, hi = idx[0], idx[-1] + 1
        scatter = hi - lo != len(idx)
        if not scatter:
            acts, state, contacts = self._actions[lo:hi], self._state[lo:hi], self._contacts[lo:hi]
            out, people = self._out[lo:hi], self._people[lo:hi]
        else:  # step the others through copies of their rows
            acts, state, contacts = self._actions[idx], self._state[idx], self._contacts[idx]
            out, people = self._out[idx], self._people[idx]

        def physics() -> None:
            if scatter:  # the commands were written into the copy: the worlds' views read them
                self._out[idx] = out
            for j, k in enumerate(idx):
                ws = sims[k]
                ws._physics()
                state[j] = ws.sim.state
                contacts[j] = ws.sim.contacts

        _core.step_worlds(
            [sims[k].world for k in idx],
            acts.reshape(-1),
            physics,
            state.reshape(-1),
            contacts.reshape(-1),
            out.reshape(-1),
            people.reshape(-1),
            threads=1,
        )
        if scatter:
            self._out[idx] = out
            self._people[idx] = people

    def _observations(self) -> dict[str, np.ndarray]:
        """Every world's robot-0 observation, batched (float32, one fresh copy)."""
        data = self._out[:, : self._stride].astype(np.float32)
        lay, n, ws = self._layout, self.num_envs, self.sims[0]

        def part(name: str, *shape: int) -> np.ndarray:
            off, length = lay[name]
            return data[:, off : off + length].reshape(n, *shape)

        obs = {
            "robot": part("obs_robot", -1),
            "people": part("obs_people", ws.k_nearest, _core.PERSON_FEATURES),
            "people_mask": part("obs_people_mask", -1),
            "lidar": part("obs_lidar", -1),
        }
        if ws.subgoal > 0.0:
            obs["subgoal"] = part("obs_subgoal", -1)
        return obs

    def _infos(self, present: list[int], ended: list[int]) -> dict[str, Any]:
        """The plain env's info keys as batched arrays with ``_key`` masks (worlds `present`).

        Worlds not present hold zeros (None for ``planner_mode``). The metrics of the worlds in
        `ended` are added under ``metrics`` (masked).
        """
        n = self.num_envs
        everyone = len(present) == n
        mask = np.ones(n, dtype=bool) if everyone else np.zeros(n, dtype=bool)
        if not everyone:
            mask[present] = True
        # Every info column of every world in one copy, one row per column (the infos' arrays
        # are its rows).
        vals = self._out[:, self._info_cols].T.copy()
        if not everyone:
            vals[:, ~mask] = 0.0
        nterms = len(REWARD_KEYS)
        infos: dict[str, Any] = {}
        for j, key in enumerate(REWARD_KEYS):
            infos[key], infos[f"_{key}"] = vals[j], mask.copy()
        infos["is_success"], infos["_is_success"] = vals[nterms] != 0.0, mask.copy()
        infos["collision"], infos["_collision"] = vals[nterms + 1] != 0.0, mask.copy()
        if self._planning:
            off, length = self._layout["planner_action"]
            actions = self._out[:, off : off + length].astype(np.float32)
            if not everyone:
                actions[~mask] = 0.0
            infos["planner_action"], infos["_planner_action"] = actions, mask.copy()
            modes = np.full(n, None, dtype=object)
            codes = vals[nterms + 2].tolist()
            for k in present:
                modes[k] = PLANNER_MODES[int(codes[k])]
            infos["planner_mode"], infos["_planner_mode"] = modes, mask.copy()
        infos["time_of_day"], infos["_time_of_day"] = vals[nterms + 3], mask.copy()
        for k in ended:
            infos = self._add_info(infos, {"metrics": self._metrics(k)}, k)
        return infos

    def _metrics(self, k: int) -> EpisodeMetrics:
        """World k's episode metrics; a broken record's error names the world and its reset seed.

        Raises:
            InvariantError: The record broke one of its invariants (a bug in proxemic): its
                ``file`` names the scene, the world, the seed given to ``reset`` (and the
                autoresets since) and the core's episode.
        """
        try:
            return self.sims[k].world.episode_metrics([0])[0]
        except InvariantError as e:
            seed, autoresets = self._seeds[k]
            since = f", {autoresets} autoreset(s) since" if autoresets else ""
            episode = f"vector env {self.sims[k].scenario['scene']['name']}, world {k}, reset(seed={seed}){since}"
            raise invariant_in(episode, e) from e


def _check_actions(actions: Any, n: int) -> np.ndarray:
    """`actions` as an (n, 3) float64 array of finite values; :class:`InputError` otherwise."""
    expected = f"a ({n}, 3) array of finite real numbers in [-1, 1] (one action per world)"
    try:
        a = np.asarray(actions)
    except (ValueError, TypeError):
        raise input_error("actions", expected, repr(actions)) from None
    if a.shape != (n, 3) or a.dtype.kind not in REAL_KINDS:
        raise input_error("actions", expected, f"shape {a.shape} of {a.dtype}")
    a = a.astype(np.float64)
    if not np.isfinite(a).all():
        bad = int(np.argwhere(~np.isfinite(a))[0][0])
        raise input_error(f"actions[{bad}]", "3 finite real numbers in [-1, 1]", str(a[bad].tolist()))
    return a


def vector_env(scenario: str | Path | _core.Scenario = "museum", num_envs: int = 2, **kwargs: Any) -> ProxemicVectorEnv:
    """`num_envs` worlds of `scenario` as a vector env stepped in one core call.

    See :class:`ProxemicVectorEnv` for the keyword arguments, the autoreset and the seeding.
    """
    return ProxemicVectorEnv(scenario, num_envs, **kwargs)
