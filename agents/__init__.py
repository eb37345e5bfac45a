"""Scripted (non-learning) agents for the bbgym environments: callables ``obs -> action``."""

from agents.sail_autopilot import VMGAutopilot, sailing_tables
from agents.sail_simple import SimpleSailController
from agents.throw_agent import ThrowSolverAgent, ToppleAgent
from agents.throw_solver import solve_throw

__all__ = [
    "SimpleSailController",
    "VMGAutopilot",
    "sailing_tables",
    "ThrowSolverAgent",
    "ToppleAgent",
    "solve_throw",
]
