"""Scripted (non-learning) agents for the bbgym environments: callables ``obs -> action``."""

from agents.sail_simple import SimpleSailController
from agents.throw_agent import ThrowSolverAgent, ToppleAgent
from agents.throw_solver import solve_throw

__all__ = ["SimpleSailController", "ThrowSolverAgent", "ToppleAgent", "solve_throw"]
