"""Renderers. pygame is imported lazily by the renderers themselves, not here."""

from bbgym.render.sail_view import SailRenderer, SailScene
from bbgym.render.throw_view import ThrowRenderer, ThrowScene, ThrowScreen
from bbgym.render.topple_view import ToppleRenderer, ToppleScene

__all__ = [
    "SailRenderer",
    "SailScene",
    "ThrowRenderer",
    "ThrowScene",
    "ThrowScreen",
    "ToppleRenderer",
    "ToppleScene",
]
