"""Gymnasium registration of the bundled scenarios."""

from __future__ import annotations

import gymnasium as gym

#: Environment id -> bundled scenario name.
ENV_IDS: dict[str, str] = {
    "proxemic/Museum-v0": "museum",
}


def register_envs() -> None:
    """Registers every bundled scenario as a gymnasium environment (idempotent)."""
    for env_id, scenario in ENV_IDS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="proxemic.env:ProxemicEnv", kwargs={"scenario": scenario})
