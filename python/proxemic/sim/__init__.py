"""MuJoCo side of proxemic: build the model from a scenario, step it, read it, render it.

The model is assembled with ``mujoco.MjSpec`` from the validated scenario (a dict from the Rust
core) and the MJCF assets in ``proxemic/data/models``: static geoms for walls and furniture, one
Pepper-like base per robot (``robot_<i>/``, slide-x, slide-y, hinge-yaw joints with robot-frame
velocity servos), one mocap body per person (``person_<i>/``). Mocap bodies generate contacts
only with the robots, so the contacts read back are exactly robot-person, robot-static and
robot-robot events.

- :mod:`proxemic.sim.model`: the physics and render models built from the scenario;
- :mod:`proxemic.sim.simulation`: :class:`Simulation`, stepping the physics a control period at a
  time and reading the robots' states and contacts;
- :mod:`proxemic.sim.reduced`: the reduced and crowd models the periods without (or with few)
  people in reach are stepped on, bit for bit alike;
- :mod:`proxemic.sim.render`: the render model and its offscreen frames;
- :mod:`proxemic.sim.timer`: MuJoCo's default timer callback, off while stepping.
"""

from __future__ import annotations

import os

# MuJoCo chooses its OpenGL backend when it is imported: pick an offscreen one first when there is
# no display (see `ensure_gl_backend`), or rendering fails with "no OpenGL platform library".
if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
    os.environ["MUJOCO_GL"] = "egl"

from proxemic.sim.model import build_spec, models_dir
from proxemic.sim.simulation import Simulation
from proxemic.sim.timer import timer_off

__all__ = ["Simulation", "build_spec", "ensure_gl_backend", "models_dir", "timer_off"]


def ensure_gl_backend() -> str:
    """Chooses an offscreen OpenGL backend before MuJoCo creates a context.

    Honours an existing ``MUJOCO_GL``; otherwise uses EGL when no display is available (both EGL
    and OSMesa work on CPU-only machines with Mesa's llvmpipe). Returns the backend name.
    """
    if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
        os.environ["MUJOCO_GL"] = "egl"
    return os.environ.get("MUJOCO_GL", "glfw")
