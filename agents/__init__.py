"""Scripted (non-learning) agents for the bbgym environments: callables ``obs -> action``."""

from .sail_autopilot import VMGAutopilot, sailing_tables
from .sail_simple import SimpleSailController
from .throw_agent import ThrowSolverAgent, ToppleAgent
from .throw_solver import solve_throw

__all__ = [
    "SimpleSailController",
    "VMGAutopilot",
    "sailing_tables",
    "ThrowSolverAgent",
    "ToppleAgent",
    "solve_throw",
]
