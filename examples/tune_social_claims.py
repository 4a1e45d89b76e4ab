"""The figures of the social-vs-A* claims on the TUNING split, to choose the social planner's constants.

``tests/test_social_vs_astar.py`` asserts the claims on the test split of :mod:`proxemic.splits`;
this script reads the same figures, with the same readings (it loads that module's helpers), on
tuning seeds only, so a constant chosen by looking at its output never saw a test-split result::

    python examples/tune_social_claims.py                      # 20 museum, 20 care-center seeds, 50 scenes
    python examples/tune_social_claims.py --episodes 40 --scenes 100
    python examples/tune_social_claims.py --cache out/tune_claims_baselines.json

The other planners (the baselines ``astar`` and ``astar_orca``, and the papers' planners whose
rates are printed beside them) do not change when only ``social`` is tuned: with ``--cache``
their records are stored on the first run and reused, and only ``social`` is re-run.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import multiprocessing as mp
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

from proxemic import splits

ROOT = Path(__file__).resolve().parent.parent


def claims_module() -> ModuleType:
    """``tests/test_social_vs_astar.py``, loaded as a module (its readings and runner).

    The tests folder goes on ``sys.path`` as pytest puts it (the module imports a sibling test module).
    """
    path = ROOT / "tests" / "test_social_vs_astar.py"
    if str(path.parent) not in sys.path:
        sys.path.insert(0, str(path.parent))
    spec = importlib.util.spec_from_file_location("claims", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules["claims"] = mod
    spec.loader.exec_module(mod)
    return mod


C = claims_module()


def _run_one(args: tuple[str, int, tuple[str, ...]]) -> dict[str, list[dict[str, Any]]]:
    scene, seed, planners = args
    C.PLANNERS = planners
    return C._run(scene, (seed,))  # type: ignore[no-any-return]


def run(scene: str, seeds: tuple[int, ...], planners: tuple[str, ...], workers: int) -> dict[str, Any]:
    """Records of `planners` on `seeds` of `scene` (the claims' runner, `workers` processes)."""
    with mp.get_context("fork").Pool(workers) as pool:
        parts = pool.map(_run_one, [(scene, s, planners) for s in seeds])
    return {p: [r for part in parts for r in part[p]] for p in planners}


def _clean(rec: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in rec.items() if isinstance(v, (int, float, str, bool, type(None)))}


def figures(rec: dict[str, Any]) -> dict[str, str]:
    """The claim figures of one scene set (social against each baseline)."""
    out: dict[str, str] = {}
    room = C.roomy(rec[C.SOCIAL])
    out["intimate"] = f"{len(C.intimate_entries(rec[C.SOCIAL]))}/{len(room)} roomy episodes entered"
    gaps = sorted(r["gap_person_min"] for r in room if r["gap_person_min"] is not None)
    if gaps:
        out["intimate"] += f" (min gap {gaps[0]:.2f} m, median {gaps[len(gaps) // 2]:.2f} m)"
    for name, (reading, cut) in C.REDUCTIONS.items():
        s = sum(map(reading, rec[C.SOCIAL]))
        parts = []
        for b in C.BASELINES:
            a = sum(map(reading, rec[b]))
            less = (1 - s / a) if a > 0 else math.nan
            parts.append(f"{b} {a:.1f} ({less:.0%} less, need {cut:.0%})")
        out[name] = f"social {s:.1f}; " + "; ".join(parts)
    for key in ("collision", "timeout", "success"):
        out[key] = ", ".join(f"{p} {C.rate(rec[p], key):.1%}" for p in C.PLANNERS)
    for b in C.BASELINES:
        s, a = C._paired(rec, "time_to_goal", b)
        if len(s) >= 2:
            r, lo, hi = C.paired_ratio(s, a)
            out[f"time/{b}"] = f"{r:.3f} [{lo:.3f}, {hi:.3f}] over {len(s)} pairs (need <= 1.3)"
    return out


def main() -> None:
    """Runs the tuning seeds and prints the figures."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--episodes", type=int, default=20, help="tuning episode seeds per bundled scene")
    ap.add_argument("--scenes", type=int, default=50, help="tuning generated scenes")
    ap.add_argument("--offset", type=int, default=0, help="first tuning seed (episodes and scenes)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--sets", default=",".join(C.SCENE_SETS), help="scene sets, comma separated")
    ap.add_argument("--cache", type=Path, default=None, help="JSON file caching the baselines' records")
    args = ap.parse_args()
    cache: dict[str, Any] = {}
    if args.cache is not None and args.cache.exists():
        cache = json.loads(args.cache.read_text())
    for scene in args.sets.split(","):
        pool = splits.TUNING_SCENE_SEEDS if scene == C.GENERATED else splits.TUNING_EPISODE_SEEDS
        n = args.scenes if scene == C.GENERATED else args.episodes
        seeds = tuple(pool[args.offset : args.offset + n])
        assert not set(seeds) & set(splits.TEST_EPISODE_SEEDS + splits.TEST_SCENE_SEEDS)
        key = f"{scene}:{seeds[0]}-{seeds[-1]}"
        others = [p for p in C.PLANNERS if p != C.SOCIAL]
        if all(p in cache.get(key, {}) for p in others):
            rec = {**cache[key], **run(scene, seeds, (C.SOCIAL,), args.workers)}
        else:  # not cached, or cached before a planner was added to the claims' runner
            rec = run(scene, seeds, C.PLANNERS, args.workers)
            cache[key] = {p: [_clean(r) for r in rec[p]] for p in others}
        print(f"== {scene} (tuning seeds {seeds[0]}-{seeds[-1]})")
        for k, v in figures(rec).items():
            print(f"  {k:24s} {v}")
        sys.stdout.flush()
    if args.cache is not None:
        args.cache.parent.mkdir(parents=True, exist_ok=True)
        args.cache.write_text(json.dumps(cache))


if __name__ == "__main__":
    main()
