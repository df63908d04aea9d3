"""What an experiment can be: each module here runs one kind of experiment (`run(experiment, results)`).
Importing the package makes blend_scenes/ importable (core_scenes), whatever order a module's imports
are sorted in, also for a kind run as a child process (`python -m kinds.<name>`)."""

import os
import sys

_SCENES = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "blend_scenes")
if _SCENES not in sys.path:
    sys.path.insert(0, _SCENES)
