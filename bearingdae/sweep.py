"""Former home of the sweeps, now :mod:`bearingdae.studies.sweep` (split by job: parse, store,
worker, cluster, assemble).

Kept as a plain re-export (no warning: the CLI, skidmap and paper used it, and scripts import
``from bearingdae.sweep import run_sweep``); new code imports ``bearingdae.studies.sweep``. To
patch a name in a test, patch the module that looks it up (``bearingdae.studies.sweep.cluster``
for ``execute_run``), not this one.
"""

from .studies.sweep import *  # noqa: F401,F403
from .studies.sweep import (  # noqa: F401  (the private names `import *` leaves out)
    _TOP_KEYS,
    _read_toml,
    _flatten,
    _check_key,
    _axis_values,
    _dim_names,
    _resolve_base,
    _settings,
    _AXIS_UNITS,
    _coord,
    _LOCAL_TIMEOUTS,
    _client,
    _cost,
    _execute,
)
