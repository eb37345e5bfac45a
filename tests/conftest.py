"""Test-suite settings.

Under CI (``CI`` set, as ``.ci/run`` is run) hypothesis replays the same examples every run
(``derandomize``), so a submission's result does not depend on which examples a run
happens to draw; locally each run draws new ones, and ``scripts/fuzz.py`` explores at
length.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
