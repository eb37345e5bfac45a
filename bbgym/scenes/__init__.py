"""The course as runnable scenes: each demo of the course text as a small pure, batched
physics setup on the envs' array namespace, with a view and a tested claim.

    bbgym scene --list
    bbgym scene three-beachballs-1 --steps 600 --out balls.gif --param dt_s=0.05

A scene (:class:`~bbgym.scenes.scene.Scene`) is declared the way an env family is: its
parameters, its initial state and step, what it measures and what a frame shows.
:func:`~bbgym.scenes.scene.simulate` runs one on NumPy or torch;
:class:`~bbgym.scenes.view.SceneView` draws it (the ``render`` extra). The registry below
lists them in the text's order; each module holds one family of demos.
"""

from __future__ import annotations

from bbgym.scenes.boat import SCENES as BOAT
from bbgym.scenes.collisions import SCENES as COLLISIONS
from bbgym.scenes.flight import SCENES as FLIGHT
from bbgym.scenes.fluid import SCENES as FLUID
from bbgym.scenes.friction import SCENES as FRICTION
from bbgym.scenes.projectiles import SCENES as PROJECTILES
from bbgym.scenes.rotations import SCENES as ROTATIONS
from bbgym.scenes.scene import Scene, Trajectory, simulate
from bbgym.scenes.springs import SCENES as SPRINGS
from bbgym.scenes.waves import SCENES as WAVES
from bbgym.scenes.wind import SCENES as WIND

__all__ = ["SCENES", "Scene", "Trajectory", "get_scene", "simulate", "unknown_scene"]

SCENES: dict[str, Scene] = {
    scene.name: scene
    for scene in sorted(
        (
            *PROJECTILES,
            *COLLISIONS,
            *ROTATIONS,
            *FRICTION,
            *SPRINGS,
            *WIND,
            *FLIGHT,
            *BOAT,
            *WAVES,
            *FLUID,
        ),
        key=lambda scene: int(scene.section[1:]),
    )
}
"""Every scene by name, in the course text's order (by section; within one, as declared)."""


def get_scene(name: str) -> Scene:
    """The scene called ``name``, or a ``KeyError`` saying :func:`unknown_scene`."""
    try:
        return SCENES[name]
    except KeyError:
        raise KeyError(unknown_scene(name)) from None


def unknown_scene(name: str) -> str:
    """What to say of a scene name that is not one: the nearest name, where one is near
    (``"unknown scene 'magnos': did you mean 'magnus'?"``), then the names.

    Args:
        name: The name as the user gave it.

    Returns:
        The message.
    """
    from bbgym.spec import nearest

    names = ", ".join(SCENES)
    near = nearest(name, SCENES)
    if near is None:
        return f"unknown scene {name!r}; the scenes: {names}"
    return f"unknown scene {name!r}: did you mean {near!r}? The scenes: {names}"
