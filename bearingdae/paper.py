"""Former home of the paper set, now :mod:`bearingdae.studies.paper`.

Kept as a plain re-export so that ``from bearingdae.paper import run_paper`` keeps working; new
code imports ``bearingdae.studies.paper``.
"""

from .studies.paper import *  # noqa: F401,F403
from .studies.paper import PAPER_SWEEPS, run_paper  # noqa: F401
