"""satflock: simulate and steer satellite swarms and clusters in Earth orbit under J2.

SI units throughout (m, s, kg, rad); relative states are in the Hill LVLH frame (x radial out, y
along-track, z orbit normal) about the LVLH origin, inertial states in EME2000 (see docs/python.md).
"""

from ._native import (
    CampaignError,
    LawContext,
    Scenario,
    ScenarioError,
    SimulationError,
    __version__,
    budget,
    characterize,
    propagate,
)
from ._campaign import campaign
from ._compare import compare
from ._run import RunResult, Simulation, Trajectory, run

__all__ = [
    "CampaignError",
    "LawContext",
    "RunResult",
    "Scenario",
    "ScenarioError",
    "Simulation",
    "SimulationError",
    "Trajectory",
    "__version__",
    "budget",
    "campaign",
    "characterize",
    "compare",
    "propagate",
    "run",
]
