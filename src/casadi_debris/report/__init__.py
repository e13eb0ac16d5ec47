"""Reports: results in display units, paper-vs-toolkit comparisons, tables, run folders.

This is an edge package: it turns SI results into fields whose names carry
their display unit (``torque_max_mNm``), holds the paper's published figures
and tolerances (:mod:`casadi_debris.report.paper`) and writes run folders
atomically.
"""
