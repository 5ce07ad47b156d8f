"""Former home of the work-precision study, now :mod:`bearingdae.studies.workprecision`.

Kept so that ``from bearingdae import workprecision`` keeps working for one release; new code
imports ``bearingdae.studies.workprecision``.
"""

import warnings

warnings.warn("bearingdae.workprecision moved to bearingdae.studies.workprecision; the old name "
              "goes in the next release", DeprecationWarning, stacklevel=2)

from .studies.workprecision import *  # noqa: F401,F403
from .studies.workprecision import __doc__ as _doc  # noqa: F401
from .studies.workprecision.runs import _execute  # noqa: F401
