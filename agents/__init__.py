"""Scripted (non-learning) agents for the bbgym environments."""

from agents.sail_simple import SimpleSailController

__all__ = ["SimpleSailController"]
