"""What reads a result: the numbers an engineer takes from a run's states or its Dataset.

Stage: run -> **analysis** -> results. Steady-state summaries and orbit folding
(``summary``), error bars of chaotic time series (``statistics``, ``headline``, ``trends``),
rating life, film and power loss (``engineering``, ``rating_life``), the scene's quasi-static
state and stiffness (``static_state``, ``stiffness``), end flanges, cage whirl and ring vibration
(``flange``, ``whirl``, ``vibration``, ``spectrum``) and the plausibility guards (``guards``).
They sit below ``results``: the record of a run (results/dataset.py, results/streamed_record.py)
computes these quantities into the Dataset it builds, so the record imports them, never the
other way round.
"""
