"""Renderers. pygame is imported lazily by the renderers themselves, not here."""

from bbgym.render.sail_view import SailRenderer, SailScene

__all__ = ["SailRenderer", "SailScene"]
