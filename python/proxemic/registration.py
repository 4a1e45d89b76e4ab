"""Gymnasium registration of the bundled scenarios."""

from __future__ import annotations

import gymnasium as gym

#: Environment id -> bundled scenario name.
ENV_IDS: dict[str, str] = {
    "proxemic/Museum-v5": "museum",
    "proxemic/CareCenter-v5": "care_center",
    "proxemic/Daza2021Fig15-v4": "daza2021_fig15",
    "proxemic/Daza2021Path1-v4": "daza2021_path1",
    "proxemic/Daza2021Path2-v4": "daza2021_path2",
    "proxemic/Daza2021Path3-v4": "daza2021_path3",
    "proxemic/Daza2021Path4-v5": "daza2021_path4",
    "proxemic/Daza2021Path5-v6": "daza2021_path5",
    "proxemic/Sousa2022Fig16-v5": "sousa2022_fig16",
    "proxemic/Sousa2022Fig17-v5": "sousa2022_fig17",
    "proxemic/CalderitaExp1-v6": "calderita_exp1",
    "proxemic/CalderitaExp2-v5": "calderita_exp2",
}


#: The environment id of generated scenes: ``gym.make(GENERATED_ENV_ID, scenario="generated/3?robots=1")``
#: (default ``generated/0``; see :func:`proxemic.scenarios.generate`).
GENERATED_ENV_ID = "proxemic/Generated-v5"

#: The environment id of the Francis et al. 2023 archetypes:
#: ``gym.make(FRANCIS2023_ENV_ID, archetype="crossing_90", scene_seed=3)`` (see :mod:`proxemic.francis2023`).
FRANCIS2023_ENV_ID = "proxemic/Francis2023-v7"


def register_envs() -> None:
    """Registers every bundled scenario, and generated scenes, as gymnasium environments (idempotent)."""
    if GENERATED_ENV_ID not in gym.registry:
        gym.register(id=GENERATED_ENV_ID, entry_point="proxemic.env:ProxemicEnv", kwargs={"scenario": "generated/0"})
    if FRANCIS2023_ENV_ID not in gym.registry:
        gym.register(id=FRANCIS2023_ENV_ID, entry_point="proxemic.francis2023:make_env")
    for env_id, scenario in ENV_IDS.items():
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="proxemic.env:ProxemicEnv", kwargs={"scenario": scenario})
