"""Scripted (non-learning) agents for the bbgym environments: callables ``obs -> action``."""

from .race_racer import RaceRacer
from .sail_autopilot import VMGAutopilot, sailing_tables
from .sail_simple import SimpleSailController
from .throw_agent import ThrowSolverAgent, ToppleAgent
from .throw_solver import solve_throw

__all__ = [
    "RaceRacer",
    "SimpleSailController",
    "VMGAutopilot",
    "sailing_tables",
    "ThrowSolverAgent",
    "ToppleAgent",
    "solve_throw",
]
