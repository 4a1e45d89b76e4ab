"""Several robots as one vectorised env, with SuperSuit's standard multi-agent wrappers.

The PettingZoo parallel env of the Daza 2021 Fig. 15 crossing (four robots) is wrapped the way
parameter-sharing multi-agent RL uses it: observations flattened to one vector
(``observation_lambda_v0``), finished robots kept as zero-observation "black death" agents so
the agent count stays fixed (``black_death_v3``), every agent one sub-env of a vector env
(``pettingzoo_env_to_vec_env_v1``), and copies of the env concatenated
(``concat_vec_envs_v1``). A random shared policy then drives every robot.

Run: ``python examples/parallel_vec_env.py``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces

import proxemic
from proxemic.errors import require_extra

ss: Any = require_extra("supersuit", "multi", "examples/parallel_vec_env.py")


def make_vec_env(copies: int = 2, scenario: str = "daza2021_fig15") -> Any:
    """`copies` copies of the scenario's parallel env, one sub-env per robot, flat observations."""
    env = proxemic.parallel_env(scenario)
    env = ss.observation_lambda_v0(
        env,
        lambda obs, space, agent=None: spaces.flatten(space, obs),
        lambda space, agent=None: spaces.flatten_space(space),
    )
    env = ss.black_death_v3(env)
    vec = ss.pettingzoo_env_to_vec_env_v1(env)
    return ss.concat_vec_envs_v1(vec, copies, num_cpus=0, base_class="gymnasium")


def main(steps: int = 200, copies: int = 2) -> dict[str, Any]:
    """Runs a random shared policy for `steps` vector steps; returns what it saw."""
    vec = make_vec_env(copies)
    obs, _ = vec.reset(seed=0)
    rng = np.random.default_rng(0)
    total = np.zeros(vec.num_envs)
    for _ in range(steps):
        actions = rng.uniform(-1.0, 1.0, (vec.num_envs, 3)).astype(np.float32)
        obs, rewards, _, _, _ = vec.step(actions)
        total += rewards
    vec.close()
    result = {"num_envs": vec.num_envs, "obs_shape": obs.shape, "steps": steps, "mean_return": float(total.mean())}
    print(result)
    return result


if __name__ == "__main__":
    main()
