"""Figures drawn from a result Dataset only (never from solver internals), saved atomically.

Stage: results -> **plots**. ``plotting`` (a run's overview, the skid map and the dispatch of
``bearingdae plot``), ``paper_figures`` (the paper's figures), ``plot_engineering``,
``plot_spectrum``, ``plot_whirl``, ``plot_trends``; ``figure_common`` holds what every figure
says the same way (units, colour keys, titles) and :func:`~.figure_common.save_figure`.
"""
