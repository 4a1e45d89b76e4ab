"""MuJoCo's default timer callback, switched off while the simulation steps.

MuJoCo's Python bindings (4.x) install a timer callback at import: every step then reads the
clock some 30 times to fill ``MjData.timer`` (a tenth of a control step's physics here). The
simulation steps with it switched off (``data.timer`` stays empty; nothing else uses the
callback, so the physics is the same bit for bit) and puts it back after each step. Only that
default is switched off: a timer a user set (``mujoco.set_mjcb_time``) is left running.
"""

from __future__ import annotations

import contextlib
import ctypes
from collections.abc import Iterator
from pathlib import Path

import mujoco


def _timer_slot() -> ctypes.c_void_p | None:
    """MuJoCo's global timer callback ``mjcb_time`` (the C pointer), or None if not found."""
    folder = Path(mujoco.__file__).parent
    for lib in sorted(folder.glob("libmujoco.so*")) + sorted(folder.glob("libmujoco*.dylib")) + [folder / "mujoco.dll"]:
        try:
            return ctypes.c_void_p.in_dll(ctypes.CDLL(str(lib)), "mjcb_time")
        except (OSError, ValueError):
            continue
    return None


_TIMER = _timer_slot()
_DEFAULT_TIMER: int | None = _TIMER.value if _TIMER is not None else None


def _timer_off() -> int | None:
    """Switches the bindings' default timer off; returns it (to restore) or None if it was not on."""
    if _TIMER is None or _DEFAULT_TIMER is None or _TIMER.value != _DEFAULT_TIMER:
        return None
    _TIMER.value = None
    return _DEFAULT_TIMER


@contextlib.contextmanager
def timer_off() -> Iterator[None]:
    """MuJoCo stepped as :meth:`proxemic.sim.Simulation.step` steps it: without the bindings' default timer.

    For benches timing bare ``mj_step`` calls against the env's own (like with like).
    """
    saved = _timer_off()
    try:
        yield
    finally:
        if saved is not None:
            assert _TIMER is not None
            _TIMER.value = saved
