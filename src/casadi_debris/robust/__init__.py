"""Robust attitude control: uncertainty weight, four-block mu-synthesis, reduction, margins.

Design units are the paper's: attitude in deg, torque in mNm.
"""
