"""The jobs users run, as documented Python functions; the command line only adapts them.

- :func:`~casadi_debris.workflows.controller.load_controller`: a controller file.
- :func:`~casadi_debris.workflows.montecarlo.montecarlo`: a Monte-Carlo
  campaign written (and resumed) case by case into a folder.
- :func:`~casadi_debris.workflows.reproduce.reproduce`: the paper end to end.
- :func:`~casadi_debris.workflows.compare.compare`: fuel budgets side by side.

Nothing here prints: progress goes to the callbacks a caller passes, messages
to :mod:`logging`.
"""
