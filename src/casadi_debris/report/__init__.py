"""Reports: results in display units, paper-vs-toolkit comparisons, tables, the files of
each job's folder.

This is an edge package: it turns SI results into fields whose names carry
their display unit (``torque_max_mNm``), holds the paper's published figures
and tolerances (:mod:`casadi_debris.report.paper`) and lays out what each job's
folder holds; the writing itself (atomic files, run and campaign folders) is
:mod:`casadi_debris.store`'s.
"""
