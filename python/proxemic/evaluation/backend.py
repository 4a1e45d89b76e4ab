"""Where episodes run: a process pool or Ray tasks, results in task order."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator, Sequence
from typing import Any, TypeVar

from proxemic.errors import input_error, require_extra
from proxemic.evaluation.config import EpisodeResult, EvalConfig
from proxemic.evaluation.episodes import _run_task_kw

T = TypeVar("T")
R = TypeVar("R")


def _check_ray_address(address: str) -> None:
    """Fails fast, with a clear message, when a ``host:port`` Ray address does not answer."""
    import socket

    hostport = address.removeprefix("ray://")
    host, sep, port = hostport.rpartition(":")
    if not sep or not port.isdigit():
        return  # "auto" and other forms are left to ray.init
    try:
        socket.create_connection((host or "127.0.0.1", int(port)), timeout=5.0).close()
    except OSError as e:
        raise input_error(
            "ray_address",
            "the address of a running Ray cluster (host:port)",
            address,
            note=f"no Ray cluster answers there: {e.strerror or e}",
        ) from e


class Backend:
    """Where episodes run: a process pool or Ray tasks (a local Ray, or a cluster's address).

    Use as a context manager; :meth:`imap` yields results in task order, so the same tasks give
    the same results on any backend and any number of workers. The pool (or the Ray connection)
    lives until the ``with`` block ends, so per-process env caches survive between calls.
    """

    def __init__(self, kind: str = "process", workers: int = 1, ray_address: str | None = None) -> None:
        """Checks the backend name; nothing starts before ``with``."""
        if kind not in ("process", "ray"):
            raise input_error("backend", "'process' or 'ray'", kind)
        self.kind, self.workers, self.ray_address = kind, max(1, workers), ray_address
        self._pool: Any = None
        self._ray: Any = None

    def __enter__(self) -> Backend:
        if self.kind == "ray":
            self._ray = self._start_ray()
        elif self.workers > 1:
            import multiprocessing as mp

            ctx = mp.get_context("fork") if hasattr(os, "fork") else mp.get_context("spawn")
            self._pool = ctx.Pool(self.workers)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._pool is not None:
            self._pool.terminate()
            self._pool.join()
            self._pool = None
        if self._ray is not None:
            self._ray.shutdown()
            self._ray = None

    def _start_ray(self) -> Any:
        if self.ray_address:
            _check_ray_address(self.ray_address)
        ray: Any = require_extra("ray", "ray", "backend 'ray'")
        try:
            if self.ray_address:
                ray.init(address=self.ray_address, ignore_reinit_error=True, log_to_driver=False)
            else:
                ray.init(num_cpus=self.workers, ignore_reinit_error=True, log_to_driver=False, include_dashboard=False)
        except Exception as e:  # ray raises ConnectionError, RuntimeError, ... for a dead address
            raise input_error(
                "ray_address",
                "the address of a running Ray cluster",
                str(self.ray_address or "a local cluster"),
                note=f"could not connect: {e}",
            ) from e
        return ray

    def imap(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """``fn`` over `items` (``fn`` a module-level function), results in order."""
        if self._ray is not None:
            remote = self._ray.remote(fn)
            refs = [remote.remote(item) for item in items]
            for ref in refs:
                yield self._ray.get(ref)
        elif self._pool is not None:
            yield from self._pool.imap(fn, items, chunksize=max(1, len(items) // (8 * self.workers)))
        else:
            for item in items:
                yield fn(item)


def iter_results(cfg: EvalConfig) -> Iterator[EpisodeResult]:
    """Runs every episode of `cfg` on its backend, yielding results in task order.

    On a multi-robot scene an episode yields one result per robot (robot 0 first), unless user
    policies are evaluated: a policy drives robot 0 only, so then every planner is scored on robot 0
    too (like for like; see :func:`policy_robot_note`).
    """
    keep = [(t, (t[2] - cfg.seed) < cfg.keep_trajectories) for t in cfg.tasks()]
    with Backend(cfg.backend, cfg.workers, cfg.ray_address) as backend:
        for res in backend.imap(_run_task_kw, keep):
            yield res
            if not cfg.policies:  # a policy drives robot 0 only: everyone is scored on robot 0
                yield from res.others
