"""guardsim: coverage path planning for guards in games.

Load a level, build its scene (the pymunk world, the coverage grid and the vision), and walk a guard
over it tick by tick until it has seen every reachable cell::

    import guardsim

    scene = guardsim.Scene.from_level(guardsim.load_level("levels/square.json"))
    simulation = guardsim.Simulation(scene, "ripplefront")
    simulation.reset(seed=0)
    while not simulation.done:
        simulation.step()
    trace = simulation.trace()

See docs/api.md. Names are imported on first use, so ``import guardsim`` (and the command line's
``--help`` and ``validate``) stays quick and does not load the compiled kernels.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

# Public name -> the module that defines it.
_SOURCES = {
    "GuardsimError": "guardsim.errors",
    "LevelError": "guardsim.errors",
    "LimitError": "guardsim.errors",
    "OutputError": "guardsim.errors",
    "CheckError": "guardsim.errors",
    "PatrolError": "guardsim.errors",
    "PointError": "guardsim.errors",
    "ArgumentError": "guardsim.errors",
    "PlannerError": "guardsim.errors",
    "RegressionError": "guardsim.errors",
    "TraceError": "guardsim.errors",
    "GuardSpec": "guardsim.level",
    "IntruderSpec": "guardsim.level",
    "Level": "guardsim.level",
    "Camera": "guardsim.level",
    "Light": "guardsim.level",
    "load_level": "guardsim.importers.loading",
    "ImportedLevel": "guardsim.importers.imported",
    "ImportOptions": "guardsim.importers.options",
    "parse_level": "guardsim.level",
    "World": "guardsim.world",
    "CoverageGrid": "guardsim.grid",
    "LineOfSight": "guardsim.vision",
    "VisionCone": "guardsim.vision",
    "Scene": "guardsim.scene",
    "episode_generator": "guardsim.starts",
    "PLANNERS": "guardsim.planners",
    "Planner": "guardsim.planners",
    "make_planner": "guardsim.planners",
    "Simulation": "guardsim.simulation",
    "run_episode": "guardsim.motion",
    "Trace": "guardsim.trace",
    **dict.fromkeys(("AwarenessMeter", "DetectionModel", "GuardDetection"), "guardsim.detection"),
    **dict.fromkeys(("light_map", "light_at"), "guardsim.detection.light"),
    **dict.fromkeys(("visibility", "meter_gain"), "guardsim.kernels.meter"),
    "level_watch": "guardsim.detection.watch",
    "sneak_check": "guardsim.sneak",
    **dict.fromkeys(("Patrol", "patrol_setup", "plan_patrol", "read_patrol"), "guardsim.patrol"),
    "ViewTable": "guardsim.vision.table",
    "compile_kernels": "guardsim.kernels.ahead",
    **dict.fromkeys(
        ("AlertEpisode", "AlertRules", "GameGuards", "alert_episode", "check_alert_trace", "run_alerts"),
        "guardsim.alert",
    ),
    **dict.fromkeys(("plan_alert_batch", "run_alert_batch"), "guardsim.alert.batch_run"),
    **dict.fromkeys(("ContinuousSimulation", "GuardMotion"), "guardsim.motion"),
    **dict.fromkeys(("analyse", "report", "diff"), "guardsim.design"),
    "fortify": "guardsim.design.fortify",
}

__all__ = ["__version__", *_SOURCES]


def __getattr__(name: str) -> Any:
    source = _SOURCES.get(name)
    if source is None:
        raise AttributeError(f"module 'guardsim' has no attribute {name!r}")
    module, _, attribute = source.partition(":")
    value = getattr(importlib.import_module(module), attribute or name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)


if TYPE_CHECKING:
    from guardsim.alert import AlertEpisode as AlertEpisode
    from guardsim.alert import AlertRules as AlertRules
    from guardsim.alert import GameGuards as GameGuards
    from guardsim.alert import alert_episode as alert_episode
    from guardsim.alert import check_alert_trace as check_alert_trace
    from guardsim.alert import run_alerts as run_alerts
    from guardsim.alert.batch_run import plan_alert_batch as plan_alert_batch
    from guardsim.alert.batch_run import run_alert_batch as run_alert_batch
    from guardsim.design import analyse as analyse
    from guardsim.design import diff as diff
    from guardsim.design import report as report
    from guardsim.design.fortify import fortify as fortify
    from guardsim.detection import AwarenessMeter as AwarenessMeter
    from guardsim.detection import DetectionModel as DetectionModel
    from guardsim.detection import GuardDetection as GuardDetection
    from guardsim.detection.light import light_at as light_at
    from guardsim.detection.light import light_map as light_map
    from guardsim.detection.watch import level_watch as level_watch
    from guardsim.errors import ArgumentError as ArgumentError
    from guardsim.errors import CheckError as CheckError
    from guardsim.errors import GuardsimError as GuardsimError
    from guardsim.errors import LevelError as LevelError
    from guardsim.errors import LimitError as LimitError
    from guardsim.errors import OutputError as OutputError
    from guardsim.errors import PatrolError as PatrolError
    from guardsim.errors import PlannerError as PlannerError
    from guardsim.errors import PointError as PointError
    from guardsim.errors import RegressionError as RegressionError
    from guardsim.errors import TraceError as TraceError
    from guardsim.grid import CoverageGrid as CoverageGrid
    from guardsim.importers.imported import ImportedLevel as ImportedLevel
    from guardsim.importers.loading import load_level as load_level
    from guardsim.importers.options import ImportOptions as ImportOptions
    from guardsim.kernels.ahead import compile_kernels as compile_kernels
    from guardsim.kernels.meter import meter_gain as meter_gain
    from guardsim.kernels.meter import visibility as visibility
    from guardsim.level import Camera as Camera
    from guardsim.level import GuardSpec as GuardSpec
    from guardsim.level import IntruderSpec as IntruderSpec
    from guardsim.level import Level as Level
    from guardsim.level import Light as Light
    from guardsim.level import parse_level as parse_level
    from guardsim.motion import ContinuousSimulation as ContinuousSimulation
    from guardsim.motion import GuardMotion as GuardMotion
    from guardsim.motion import run_episode as run_episode
    from guardsim.patrol import Patrol as Patrol
    from guardsim.patrol import patrol_setup as patrol_setup
    from guardsim.patrol import plan_patrol as plan_patrol
    from guardsim.patrol import read_patrol as read_patrol
    from guardsim.planners import PLANNERS as PLANNERS
    from guardsim.planners import Planner as Planner
    from guardsim.planners import make_planner as make_planner
    from guardsim.scene import Scene as Scene
    from guardsim.simulation import Simulation as Simulation
    from guardsim.sneak import sneak_check as sneak_check
    from guardsim.starts import episode_generator as episode_generator
    from guardsim.trace import Trace as Trace
    from guardsim.vision import LineOfSight as LineOfSight
    from guardsim.vision import VisionCone as VisionCone
    from guardsim.vision.table import ViewTable as ViewTable
    from guardsim.world import World as World
