r"""Train a PPO agent with stable-baselines3 on proxemic scenes, save it, evaluate it like a planner.

Needs the ``rl`` extra: ``pip install 'proxemic[rl]'`` (stable-baselines3 and torch; why this
framework and not SB3's JAX port: ``docs/training.md``).

Two kinds of training set:

* one scene (``--scenario daza2021_path3``, the default: Daza et al. 2021, Path 3, a 14 x 10 m
  room, two boxes, a group of two people and a robot beside the robot's 10 m west-east line),
  each episode seeded from the env's own sequence;
* ``--scenario generated-tuning``: generated scenes of the tuning split
  (``proxemic.splits.TUNING_SCENE_SEEDS``, the 12 x 12 m size ``GENERATED_SIZE`` so that every
  scene has the same observation bounds), a fresh scene drawn at every reset;
* ``--scenario mixed-tuning``: half the resets a generated scene of the tuning split at the
  generator's default size (24 x 16 m, the claims suites' size), the other half the museum or
  the care center with an episode seed of the tuning split (how the shipped ``learned`` policy
  was trained, ``docs/learned.md``).

``--subgoal M`` adds the ``subgoal`` observation key: the point M metres along the shortest path
to the goal, in the robot's frame (``[sensors] subgoal``), the way round walls that the straight
goal offset does not give.

The observation dict is flattened and scaled to about [-1, 1] by
:class:`proxemic.policy.FlatObservation` (so SB3's plain ``MlpPolicy`` applies); the env's reward
(geodesic progress, success, collision, time and personal-space terms) is used as it is.

Every finished training episode is logged (env steps so far, success, collision, personal-zone
seconds) to ``OUT/curve_<scene>.csv`` and drawn as ``OUT/curve_<scene>.png`` (success rate,
collision rate and personal-zone time against env steps); the run ends with its env steps per
second and wall time.

Train (the model is written to ``OUT/ppo_<scene>.zip``)::

    python examples/train_ppo.py --scenario daza2021_path3 --steps 200000 --out out/ppo

Evaluate it beside the planners, on the same seeds (``PROXEMIC_PPO_MODEL`` names the model;
default ``out/ppo/ppo_daza2021_path3.zip``)::

    proxemic eval --scenario daza2021_path3 --policy examples.train_ppo:make --policy-name ppo \
        --planner astar --planner astar_orca --planner astar_stop --planner social --episodes 20 \
        --out out/ppo/eval
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from proxemic.errors import require_extra
from proxemic.policy import FlatObservation, flat_observation_env

DEFAULT_SCENE = "daza2021_path3"
DEFAULT_MODEL = Path("out/ppo") / f"ppo_{DEFAULT_SCENE}.zip"
#: The training set of generated scenes of the tuning split.
GENERATED_SET = "generated-tuning"
#: The training set of generated scenes (the generator's default size, as the claims suites' set)
#: and the bundled museum and care center, tuning split.
MIXED_SET = "mixed-tuning"
#: The bundled scenes of ``MIXED_SET``.
MIXED_BUNDLED = ("museum", "care_center")
#: Generated scenes' size in the training set (m): the generator's smallest, one size for all so
#: that the goal-offset bounds (the map diagonal), hence the observation space, agree.
GENERATED_SIZE = {"width": 12.0, "height": 12.0}
#: Finished episodes per point of the learning curve.
CURVE_WINDOW = 50


def make_env(scenario: str, subgoal: float = 0.0) -> Any:
    """The single-robot env of `scenario` with flat, scaled observations.

    ``GENERATED_SET`` gives a :class:`SceneCycle` over generated scenes of the tuning split,
    ``MIXED_SET`` one over those and the museum and care center (tuning episode seeds).
    `subgoal` > 0 adds the ``subgoal`` observation key with that look-ahead (metres).
    """
    if scenario == GENERATED_SET:
        return SceneCycle(subgoal)
    if scenario == MIXED_SET:
        return SceneCycle(subgoal, MIXED_BUNDLED, size=None)
    from proxemic.env import ProxemicEnv

    return flat_observation_env(ProxemicEnv(scenario, subgoal=subgoal))


class SceneCycle(gym.Env):
    """A gymnasium env that draws a scene of the tuning split at every reset.

    Without `bundled`, a generated scene: its seed is drawn from
    ``proxemic.splits.TUNING_SCENE_SEEDS`` by the env's own random generator (seeded by
    ``reset(seed=...)``), and the episode seed is the scene seed, as in the claims suites; its
    size is `size` (``GENERATED_SIZE`` by default; None: the generator's default, 24 x 16 m, the
    size of the claims suites' generated scene set). With `bundled` (scene names), half the
    resets draw a generated scene so, the other half one of the bundled scenes (each as likely)
    with an episode seed from ``proxemic.splits.TUNING_EPISODE_SEEDS``. Observations are flat and
    scaled (:class:`proxemic.policy.FlatObservation`) by one scale for every scene: each key's
    widest bound over the generated scenes' size and the bundled scenes.
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 (gymnasium declares it an instance variable)

    def __init__(
        self,
        subgoal: float = 0.0,
        bundled: tuple[str, ...] = (),
        size: dict[str, float] | None = GENERATED_SIZE,
    ) -> None:
        """Builds the scenes to read the spaces from (`subgoal`: the ``subgoal`` key's look-ahead, m)."""
        from proxemic.env import ProxemicEnv
        from proxemic.splits import TUNING_EPISODE_SEEDS, TUNING_SCENE_SEEDS

        self._subgoal = subgoal
        self._size = size or {}
        self._seeds = TUNING_SCENE_SEEDS
        self._episode_seeds = TUNING_EPISODE_SEEDS
        self._bundled = {name: ProxemicEnv(name, subgoal=subgoal) for name in bundled}
        self._env = self._load(self._seeds[0])
        self._generated_space = self._env.observation_space
        self.flat = FlatObservation(
            _widest([self._generated_space, *(e.observation_space for e in self._bundled.values())])
        )
        self.observation_space = self.flat.space
        self.action_space = self._env.action_space
        self.scene_seed = self._seeds[0]
        self.scene = self._env.scenario["scene"]["name"]

    def _load(self, seed: int) -> Any:
        from proxemic.env import ProxemicEnv
        from proxemic.scenarios import generated_name

        return ProxemicEnv(generated_name(seed, **self._size), subgoal=self._subgoal)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict]:
        """Draws a scene (and its seed), loads it if generated, and resets it with that seed."""
        super().reset(seed=seed)
        if self._bundled and self.np_random.random() < 0.5:
            names = sorted(self._bundled)
            self.scene = names[int(self.np_random.integers(len(names)))]
            self._env = self._bundled[self.scene]
            episode = int(self._episode_seeds[int(self.np_random.integers(len(self._episode_seeds)))])
        else:
            scene = int(self._seeds[int(self.np_random.integers(len(self._seeds)))])
            if self._env not in self._bundled.values():
                self._env.close()
            self._env = self._load(scene)
            if self._env.observation_space != self._generated_space:
                raise RuntimeError(
                    f"generated scene {scene}: observation space {self._env.observation_space} differs from "
                    f"the first scene's {self._generated_space}"
                )
            self.scene_seed = episode = scene
            self.scene = self._env.scenario["scene"]["name"]
        obs, info = self._env.reset(seed=episode, options=options)
        return self.flat(obs), info

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict]:
        """One step of the current scene."""
        obs, reward, terminated, truncated, info = self._env.step(action)
        return self.flat(obs), reward, terminated, truncated, info

    def close(self) -> None:
        """Closes every scene's env."""
        self._env.close()
        for env in self._bundled.values():
            env.close()


def _widest(observation_spaces: list[Any]) -> Any:
    """One ``Dict`` space whose every key's bounds are the widest of `observation_spaces` (same keys and shapes)."""
    first = observation_spaces[0]
    return gym.spaces.Dict(
        {
            key: gym.spaces.Box(
                np.min([s[key].low for s in observation_spaces], axis=0),
                np.max([s[key].high for s in observation_spaces], axis=0),
                dtype=np.float32,
            )
            for key in first.spaces
        }
    )


def _curve_callback_base() -> type:
    return require_extra("stable_baselines3.common.callbacks", "rl", "the PPO example").BaseCallback


class LearningCurve:
    """Per finished training episode: env steps so far, success, collision, personal-zone seconds.

    ``callback()`` gives the stable-baselines3 callback that fills ``rows``; :meth:`write` saves
    them as CSV and :meth:`plot` draws the windowed rates against env steps.
    """

    def __init__(self) -> None:
        """An empty curve."""
        self.rows: list[dict[str, float]] = []

    def record(self, env_steps: int, infos: Iterable[dict[str, Any]], dones: Iterable[bool]) -> None:
        """Adds a row for each env whose episode ended at this vector step."""
        for info, done in zip(infos, dones, strict=True):
            if not done:
                continue
            metrics = info.get("metrics", {})
            self.rows.append(
                {
                    "env_steps": float(env_steps),
                    "success": float(bool(info.get("is_success", False))),
                    "collision": float(bool(info.get("collision", False))),
                    "personal_gap_time": float(metrics.get("personal_gap_time", 0.0)),
                }
            )

    def callback(self) -> Any:
        """A stable-baselines3 callback that records into this curve."""
        curve = self

        class _Callback(_curve_callback_base()):  # type: ignore[misc]
            def _on_step(self) -> bool:
                curve.record(self.num_timesteps, self.locals["infos"], self.locals["dones"])
                return True

        return _Callback()

    def windows(self, window: int = CURVE_WINDOW) -> list[dict[str, float]]:
        """Means over consecutive windows of `window` episodes, at each window's last env step."""
        out = []
        for start in range(0, len(self.rows) - window + 1, window):
            chunk = self.rows[start : start + window]
            means = {k: float(np.mean([r[k] for r in chunk])) for k in chunk[0]}
            out.append(means | {"env_steps": chunk[-1]["env_steps"]})
        return out

    def write(self, path: Path) -> None:
        """The per-episode rows as CSV."""
        with path.open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=["env_steps", "success", "collision", "personal_gap_time"])
            writer.writeheader()
            writer.writerows(self.rows)

    def plot(self, path: Path, title: str, window: int = CURVE_WINDOW) -> None:
        """Success rate, collision rate and personal-zone seconds per episode against env steps."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        points = self.windows(window)
        x = [p["env_steps"] for p in points]
        fig, axes = plt.subplots(1, 3, figsize=(12, 3.2), constrained_layout=True)
        for ax, key, label in zip(
            axes,
            ("success", "collision", "personal_gap_time"),
            ("success rate", "collision rate", "personal-zone time per episode (s)"),
            strict=True,
        ):
            ax.plot(x, [p[key] for p in points], marker=".")
            ax.set_xlabel("env steps")
            ax.set_title(label)
            ax.grid(alpha=0.3)
            if key != "personal_gap_time":
                ax.set_ylim(-0.02, 1.02)
        fig.suptitle(f"{title} (means over {window} training episodes)")
        fig.savefig(path, dpi=110)
        plt.close(fig)


def build_model(scenario: str, seed: int = 0, n_envs: int = 2, n_steps: int = 1024, subgoal: float = 0.0) -> Any:
    """An untrained PPO (SB3 defaults but `n_steps`, batch 256, 5 epochs) on `n_envs` copies of the env.

    `subgoal` > 0: the env's observation has the ``subgoal`` key with that look-ahead (metres).
    """
    torch: Any = require_extra("torch", "rl", "the PPO example")
    PPO = require_extra("stable_baselines3", "rl", "the PPO example").PPO
    make_vec_env = require_extra("stable_baselines3.common.env_util", "rl", "the PPO example").make_vec_env
    Logger = require_extra("stable_baselines3.common.logger", "rl", "the PPO example").Logger

    torch.set_num_threads(1)  # a small MLP: threads only contend on a shared machine
    vec = make_vec_env(lambda: make_env(scenario, subgoal), n_envs=n_envs, seed=seed)
    model = PPO(
        "MlpPolicy",
        vec,
        n_steps=n_steps,
        batch_size=min(256, n_steps * n_envs),
        n_epochs=5,
        learning_rate=3e-4,
        gamma=0.99,
        ent_coef=0.0,
        seed=seed,
        device="cpu",
        verbose=0,
    )
    # SB3's default logger makes an empty SB3-<date> folder in the temp dir at every learn(); ours
    # records through its own callback, so the model logs nowhere.
    model.set_logger(Logger(folder=None, output_formats=[]))
    return model


def _name(scenario: str) -> str:
    return scenario.replace("/", "_").replace("?", "_").replace("&", "_").replace("=", "")


def train(
    scenario: str,
    steps: int,
    out: Path,
    seed: int = 0,
    n_envs: int = 2,
    n_steps: int = 1024,
    model: Any = None,
    subgoal: float = 0.0,
) -> Path:
    """Trains PPO for `steps` env steps; returns the saved model's path.

    `n_steps` is the rollout length per env between updates; `model` (from :func:`build_model`)
    is trained instead of a new one; `subgoal` > 0 adds the ``subgoal`` observation key. The
    learning curve goes to ``OUT/curve_<scene>.csv`` and ``.png``; env steps per second and wall
    time are printed.
    """
    model = model if model is not None else build_model(scenario, seed, n_envs, n_steps, subgoal)
    curve = LearningCurve()
    t0 = time.perf_counter()
    model.learn(total_timesteps=steps, callback=curve.callback())
    wall = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"ppo_{_name(scenario)}.zip"
    model.save(path)
    curve.write(out / f"curve_{_name(scenario)}.csv")
    if len(curve.rows) >= CURVE_WINDOW:
        curve.plot(out / f"curve_{_name(scenario)}.png", f"PPO on {scenario}, seed {seed}")
    done = int(model.num_timesteps)
    print(
        f"trained {done} env steps on {scenario} in {wall:.0f} s ({done / wall:.0f} env steps/s with the "
        f"updates, {len(curve.rows)} episodes); saved {path}"
    )
    model.get_env().close()
    return path


def input_scale(scenario: str, subgoal: float = 0.0) -> np.ndarray:
    """The divisors :class:`FlatObservation` applies to `scenario`'s observation, flattened in its key order."""
    env = make_env(scenario, subgoal)
    flat = env.flat if isinstance(env, SceneCycle) else FlatObservation(env.unwrapped.observation_space)
    env.close()
    return np.concatenate([np.asarray(flat.scales[k]).ravel() for k in flat.keys])


def export_policy(model: Any, scenario: str, path: Path, subgoal: float = 0.0) -> Path:
    """Writes `model`'s deterministic policy as the ``.npz`` array file the core's ``learned`` planner reads.

    Arrays (float32): ``input_scale`` (the training scenes' observation divisors), then per layer
    ``w<k>`` (outputs x inputs) and ``b<k>``: SB3's ``MlpPolicy`` policy net (tanh after each
    hidden layer) followed by its linear action head; with `subgoal` > 0 (the look-ahead the
    model was trained with), ``subgoal`` (one value), so the core computes that input too.
    """
    policy = model.policy
    linears = [m for m in policy.mlp_extractor.policy_net if hasattr(m, "weight")]
    linears.append(policy.action_net)
    arrays = {"input_scale": input_scale(scenario, subgoal).astype(np.float32)}
    if subgoal > 0.0:
        arrays["subgoal"] = np.array([subgoal], np.float32)
    for k, layer in enumerate(linears):
        arrays[f"w{k}"] = layer.weight.detach().cpu().numpy().astype(np.float32)
        arrays[f"b{k}"] = layer.bias.detach().cpu().numpy().astype(np.float32)
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savez(path, **arrays)
    return path


def mean_return(policy: Callable[[np.ndarray], Any], scenario: str, seeds: Iterable[int]) -> float:
    """The mean undiscounted episode return of `policy` (flat observation in) over episode `seeds`."""
    env = make_env(scenario)
    returns = []
    for s in seeds:
        obs, _ = env.reset(seed=int(s))
        total, done = 0.0, False
        while not done:
            obs, reward, terminated, truncated, _ = env.step(policy(obs))
            total += float(reward)
            done = terminated or truncated
        returns.append(total)
    env.close()
    return float(np.mean(returns))


class PPOPolicy:
    """A saved PPO model as a proxemic policy: flat scaled observation in, deterministic action out."""

    def __init__(self, model_path: str | os.PathLike[str], observation_space: Any) -> None:
        """Loads the model (on the CPU) and the observation flattener of the env's space."""
        torch: Any = require_extra("torch", "rl", "the PPO example")
        ppo: Any = require_extra("stable_baselines3", "rl", "the PPO example").PPO
        torch.set_num_threads(1)
        self.model = ppo.load(model_path, device="cpu")
        self.flat = FlatObservation(observation_space)
        wants, gets = self.model.observation_space.shape, self.flat.space.shape
        if wants != gets:
            raise ValueError(
                f"{model_path}: the model takes observations of shape {wants}, this env's give {gets} "
                f"(keys {self.flat.keys}); a model trained with --subgoal needs the scenario's "
                "[sensors] subgoal (the same look-ahead), one trained without it a scenario without it"
            )

    def __call__(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The model's deterministic action for one observation."""
        action, _ = self.model.predict(self.flat(obs), deterministic=True)
        return np.asarray(action, dtype=np.float32)


def make(observation_space: Any, action_space: Any) -> PPOPolicy:
    """Factory for ``proxemic eval --policy examples.train_ppo:make`` (model: ``PROXEMIC_PPO_MODEL``)."""
    path = Path(os.environ.get("PROXEMIC_PPO_MODEL", DEFAULT_MODEL))
    if not path.is_file():
        raise FileNotFoundError(f"no PPO model at {path}: train one with python examples/train_ppo.py")
    return PPOPolicy(path, observation_space)


def main() -> None:
    """Trains, then evaluates the model against astar, astar_orca, astar_stop and social on the same seeds."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--scenario", default=DEFAULT_SCENE, help=f"a scene name, {GENERATED_SET} or {MIXED_SET} (training sets)"
    )
    ap.add_argument("--steps", type=int, default=150_000, help="training env steps (default: 150000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--n-envs", type=int, default=2, help="env copies stepped together (default: 2)")
    ap.add_argument("--episodes", type=int, default=20, help="evaluation episodes per policy (default: 20)")
    ap.add_argument("--out", default="out/ppo")
    ap.add_argument(
        "--subgoal",
        type=float,
        default=0.0,
        metavar="M",
        help="add the subgoal observation key, M metres along the shortest path (default 0: off)",
    )
    ap.add_argument(
        "--export", metavar="NPZ", help="also write the policy as the learned planner's array file (docs/training.md)"
    )
    args = ap.parse_args()
    import proxemic
    from proxemic.errors import MissingExtraError

    try:
        for module in ("torch", "stable_baselines3"):
            require_extra(module, "rl", "examples/train_ppo.py")
    except MissingExtraError as e:
        sys.exit(f"{e}\nFrom the repository root: pip install '.[rl]' (stable-baselines3, which brings torch)")
    path = train(args.scenario, args.steps, Path(args.out), seed=args.seed, n_envs=args.n_envs, subgoal=args.subgoal)
    if args.export:
        ppo = require_extra("stable_baselines3", "rl", "examples/train_ppo.py").PPO
        print(f"exported {export_policy(ppo.load(path, device='cpu'), args.scenario, Path(args.export), args.subgoal)}")
    if args.scenario in (GENERATED_SET, MIXED_SET) or args.episodes == 0:
        return  # a scene set: evaluate with `proxemic eval` on the test split's generated scenes
    os.environ["PROXEMIC_PPO_MODEL"] = str(path.resolve())
    result = proxemic.evaluate(
        "examples.train_ppo:make",
        name="ppo",
        scenario=args.scenario,
        episodes=args.episodes,
        seed=1000,
        planners=["astar", "astar_orca", "astar_stop", "social"],
        out=Path(args.out) / "eval",
        progress=True,
    )
    print(result.summary_markdown().split("## All metrics")[0])


if __name__ == "__main__":
    main()
