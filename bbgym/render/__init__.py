"""Drawing shared by the envs (no physics): the pygame window and its lifecycle, geometry
and annotations. Each env's own view lives in its folder (``bbgym.envs.sail.view``, ...).
pygame is imported lazily by the renderers themselves, not here."""
