r"""Train a PPO agent with stable-baselines3 on a proxemic scene, save it, evaluate it like a planner.

Needs the ``rl`` extra: ``pip install 'proxemic[rl]'`` (stable-baselines3 and torch).

The default scene is ``daza2021_path3`` (Daza et al. 2021, Path 3: a 14 x 10 m room, two boxes,
a group of two people and a robot beside the robot's 10 m west-east line), not the museum: the
museum's 52 people and 30 m routes through rooms need far more than the few hundred thousand
steps two CPU cores train in reasonable time, while this room poses the same social question (pass
a group without crossing its o-space) on a short route. The observation dict is flattened and
scaled to about [-1, 1] by :class:`proxemic.policy.FlatObservation` (so SB3's plain ``MlpPolicy``
applies); the env's reward (geodesic progress, success, collision, time and personal-space terms)
is used as it is.

Train (the model is written to ``OUT/ppo_<scene>.zip``)::

    python examples/train_ppo.py --scenario daza2021_path3 --steps 150000 --out out/ppo

Evaluate it beside the planners, on the same seeds (``PROXEMIC_PPO_MODEL`` names the model;
default ``out/ppo/ppo_daza2021_path3.zip``)::

    proxemic eval --scenario daza2021_path3 --policy examples.train_ppo:make --policy-name ppo \
        --planner astar --planner astar_orca --planner astar_stop --planner social --episodes 20 \
        --out out/ppo/eval
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from proxemic.errors import require_extra
from proxemic.policy import FlatObservation, flat_observation_env

DEFAULT_SCENE = "daza2021_path3"
DEFAULT_MODEL = Path("out/ppo") / f"ppo_{DEFAULT_SCENE}.zip"


def make_env(scenario: str) -> Any:
    """The single-robot env of `scenario` with flat, scaled observations."""
    from proxemic.env import ProxemicEnv

    return flat_observation_env(ProxemicEnv(scenario))


def train(scenario: str, steps: int, out: Path, seed: int = 0, n_envs: int = 2, n_steps: int = 1024) -> Path:
    """Trains PPO for `steps` env steps on `n_envs` copies of the env; returns the saved model's path.

    `n_steps` is the rollout length per env between updates.
    """
    torch: Any = require_extra("torch", "rl", "the PPO example")
    PPO = require_extra("stable_baselines3", "rl", "the PPO example").PPO
    make_vec_env = require_extra("stable_baselines3.common.env_util", "rl", "the PPO example").make_vec_env

    torch.set_num_threads(1)  # a small MLP: threads only contend on a shared machine
    vec = make_vec_env(lambda: make_env(scenario), n_envs=n_envs, seed=seed)
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
    t0 = time.perf_counter()
    model.learn(total_timesteps=steps)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"ppo_{scenario}.zip"
    model.save(path)
    print(f"trained {steps} steps on {scenario} in {time.perf_counter() - t0:.0f} s; saved {path}")
    vec.close()
    return path


class PPOPolicy:
    """A saved PPO model as a proxemic policy: flat scaled observation in, deterministic action out."""

    def __init__(self, model_path: str | os.PathLike[str], observation_space: Any) -> None:
        """Loads the model (on the CPU) and the observation flattener of the env's space."""
        torch: Any = require_extra("torch", "rl", "the PPO example")
        ppo: Any = require_extra("stable_baselines3", "rl", "the PPO example").PPO
        torch.set_num_threads(1)
        self.model = ppo.load(model_path, device="cpu")
        self.flat = FlatObservation(observation_space)

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
    ap.add_argument("--scenario", default=DEFAULT_SCENE)
    ap.add_argument("--steps", type=int, default=150_000, help="training env steps (default: 150000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--episodes", type=int, default=20, help="evaluation episodes per policy (default: 20)")
    ap.add_argument("--out", default="out/ppo")
    args = ap.parse_args()
    import proxemic
    from proxemic.errors import MissingExtraError

    try:
        for module in ("torch", "stable_baselines3"):
            require_extra(module, "rl", "examples/train_ppo.py")
    except MissingExtraError as e:
        sys.exit(f"{e}\nFrom the repository root: pip install '.[rl]' (stable-baselines3, which brings torch)")
    path = train(args.scenario, args.steps, Path(args.out), seed=args.seed)
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
