"""``python -m casadi_debris.cli``."""

from casadi_debris.cli import main

main()
