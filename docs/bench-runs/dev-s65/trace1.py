"""``../dev-s59/trace.py`` with the first look only (``GapConfig(second_look=False)``), to read the first look's own
drops (session 65, development only; ``runt1.sh``).

    PYTHONPATH=<clone> python trace1.py SEED TRUTH NOISE_KIND
"""
import functools
import runpy
from pathlib import Path

import voe.gap.stages as stages

stages.GapConfig = functools.partial(stages.GapConfig, second_look=False)  # trace.py imports it from here
runpy.run_path(str(Path(__file__).parent.parent / "dev-s59" / "trace.py"), run_name="__main__")
