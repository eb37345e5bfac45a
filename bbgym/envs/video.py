"""Videos of whole flights: :class:`RecordFlightVideo`.

A step of the ball envs is a whole throw; in ``render_mode="rgb_array_list"`` their
``render()`` returns the throw's flight frame by frame, then its landing. Gymnasium 1.2's
:class:`gymnasium.wrappers.RecordVideo` keeps of each such list only its last frame (the
landing) in the video, and the whole list in its ``render_history`` until its ``render()``
is called. :class:`RecordFlightVideo` keeps every frame in the video instead.
"""

from __future__ import annotations

import numpy as np
from gymnasium import logger
from gymnasium.wrappers import RecordVideo


class RecordFlightVideo(RecordVideo):
    """:class:`gymnasium.wrappers.RecordVideo` that records every frame of a list.

    With an env in ``render_mode="rgb_array_list"``, each reset and step adds all the
    frames ``env.render()`` returns (a ball env's throw: its flight, then its landing, at
    ``render_fps`` = 20 real time) to the video, not only the last; with ``rgb_array`` it
    records what :class:`~gymnasium.wrappers.RecordVideo` does. ``video_length`` counts
    frames (a recording stops after the step that exceeds it). The frames are not kept in
    ``render_history`` (Gymnasium's holds every list until the wrapper's ``render()`` is
    called: a throw's flight is about 70 frames of 0.9 MB each), so the wrapper's
    ``render()`` returns only the frames collected since the last capture.

    Example::

        env = gym.make("bbgym:<a throwing env id>", render_mode="rgb_array_list")
        env = RecordFlightVideo(env, "videos", episode_trigger=lambda e: e % 100 == 0)
    """

    def _capture_frame(self) -> None:
        assert self.recording, "Cannot capture a frame, recording wasn't started."
        rendered = self.env.render()
        frames = rendered if isinstance(rendered, list) else [rendered]
        if not frames:
            logger.warn(
                "Trying to capture render frames but 'env.render()' has just been called: "
                "there are none to capture."
            )
            return
        if all(isinstance(frame, np.ndarray) for frame in frames):
            self.recorded_frames += frames
        else:
            self.stop_recording()
            logger.warn(
                "Recording stopped: expected render() to return numpy arrays (or a list of "
                f"them), got {type(rendered)}."
            )
