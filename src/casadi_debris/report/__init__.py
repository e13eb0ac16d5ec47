"""Reports: results in display units, paper-vs-toolkit comparisons, tables, run folders.

This is an edge package: it turns SI results into fields whose names carry
their display unit (``torque_max_mNm``), holds the paper's published figures
(:data:`casadi_debris.report.common.PAPER`) and writes run folders atomically.
"""
