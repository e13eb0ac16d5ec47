"""Unit conversion factors between SI (used inside) and display units (at the edges).

Names read as "<display> per <SI>": multiply an SI value by ``MNM_PER_NM`` to get
mN m, divide a display value by it to get SI. Each factor exists once here so that
no module carries its own copy.
"""

from __future__ import annotations

import math

MN_PER_N = 1e3
MNM_PER_NM = 1e3
NM_PER_MNM = 1e-3
N_PER_MN = 1e-3
DEG_PER_RAD = 180.0 / math.pi
ARCSEC_PER_DEG = 3600.0
ARCSEC_PER_RAD = DEG_PER_RAD * ARCSEC_PER_DEG
SECONDS_PER_MINUTE = 60.0
SECONDS_PER_HOUR = 3600.0
SECONDS_PER_DAY = 86400.0
DAYS_PER_YEAR = 365.25
"""The Julian year [days]."""
SECONDS_PER_YEAR = DAYS_PER_YEAR * SECONDS_PER_DAY
US_PER_S = 1e6
M_PER_KM = 1e3
G_PER_KG = 1e3
