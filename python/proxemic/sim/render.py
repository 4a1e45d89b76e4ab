"""Rendering: the render model, posed from the physics model, and its offscreen renderers."""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from proxemic.sim.model import build_spec


class Rendering:
    """The render model of :class:`proxemic.sim.Simulation` and its frames (a base class of it)."""

    scenario: dict[str, Any]
    model: mujoco.MjModel
    data: mujoco.MjData
    _render: tuple[mujoco.MjModel, mujoco.MjData] | None
    _mocap_pos: np.ndarray
    _mocap_quat: np.ndarray
    _renderers: dict[tuple[int, int], Any]

    @property
    def render_model(self) -> mujoco.MjModel:
        """The render model (compiled on first use): the physics model plus the visual parts."""
        return self._render_pair()[0]

    @property
    def render_data(self) -> mujoco.MjData:
        """The render model's data, posed by :meth:`sync_render`."""
        return self._render_pair()[1]

    def _render_pair(self) -> tuple[mujoco.MjModel, mujoco.MjData]:
        if self._render is None:
            rm = build_spec(self.scenario, visual=True).compile()
            if (rm.nq, rm.nv, rm.nmocap, rm.nu) != (self.model.nq, self.model.nv, len(self._mocap_pos), self.model.nu):
                raise ValueError("render and physics models differ in joints or bodies")  # SHOULD NOT OCCUR
            self._render = (rm, mujoco.MjData(rm))
        return self._render

    def sync_render(self) -> None:
        """Poses the render model like the physics: joints, velocities, people, time."""
        rm, rd = self._render_pair()
        d = self.data
        rd.qpos[:] = d.qpos
        rd.qvel[:] = d.qvel
        rd.mocap_pos[:] = self._mocap_pos  # the people's, in order (every mocap body is a person)
        rd.mocap_quat[:] = self._mocap_quat
        rd.time = d.time
        mujoco.mj_kinematics(rm, rd)
        mujoco.mj_camlight(rm, rd)

    def render(self, width: int, height: int, camera: str = "top") -> np.ndarray:
        """Renders an RGB frame offscreen (EGL or OSMesa; see `ensure_gl_backend`)."""
        key = (width, height)
        self.sync_render()
        rm, rd = self._render_pair()
        renderer = self._renderers.get(key)
        if renderer is None:
            renderer = mujoco.Renderer(rm, height, width)
            self._renderers[key] = renderer
        renderer.update_scene(rd, camera=camera)
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        return renderer.render().copy()

    def close(self) -> None:
        """Releases the renderers' GL contexts."""
        for r in self._renderers.values():
            r.close()
        self._renderers.clear()
