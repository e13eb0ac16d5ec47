"""Thermospheric density from NRLMSIS 2.1 (``pymsis``), averaged over the orbit and the day.

Solar activity
--------------
NRLMSIS takes the daily solar radio flux F10.7, its 81-day mean F10.7a (in
solar flux units, 1 sfu = 1e-22 W m^-2 Hz^-1) and the daily geomagnetic index Ap.
They are always passed explicitly: without them ``pymsis`` would look the
indices up in a space-weather file it downloads, and nothing here may reach the
network. The three named levels are the long-term values of ECSS-E-ST-10-04C
(Space environment, 2008), Table 6-3, which that standard prescribes for
analyses longer than a week (the daily value then equals the 81-day mean):
clause 7.2.1.2c, of which SPENVIS keeps a copy
(https://www.spenvis.oma.be/ecss/e_st_10_04c/ecss_07_02_01.htm). The numbers
below are from memory of Table 6-3: no public copy of the table itself was at
hand to check them against.

======  =====  ======  ==
level   F10.7  F10.7a  Ap
======  =====  ======  ==
low        65      65   0
mean      140     140  15
high      250     250  45
======  =====  ======  ==

Averaging
---------
A lifetime needs the density the debris meets on average over many orbits,
as a function of its distance from the Earth's centre. The table is indexed by
that radius less the Earth's equatorial radius (the decay model's ``h = r -
R_E``); at each such ``h`` the density is averaged over

- the orbit: argument of latitude u uniform over the orbit, the position at
  geocentric latitude ``asin(sin i sin u)`` and radius ``r`` (the debris spends
  equal times at equal steps of u);
- the day: 12 local solar times (longitudes every 30 deg at 0 h UT), since the
  orbit's local time of the ascending node is not part of the problem;
- the year: the equinoxes and solstices of 2020.

NRLMSIS is given each position's geodetic latitude and altitude on the WGS-84
ellipsoid (:func:`geodetic_from_geocentric`), as it asks: the Earth's polar
radius is 21.4 km shorter than its equatorial one, so that on a polar orbit the
debris flies up to 21 km higher above the ground near the poles than ``h``
says, where the air is thinner (at 685 km and 98 deg, the mean density is a
sixth lower than at a height of ``h`` everywhere). The altitude is exact at
every point; the latitude is the one at the middle of its band of
:data:`LATITUDE_BAND_KM` of ``h`` (the geodetic latitude of a radial line moves
by 0.003 deg per 100 km: 0.007 deg off at most, where the density changes by
well under 0.1 %), since NRLMSIS recomputes its horizontal terms whenever the
latitude changes, which a latitude per height would make four times as slow.
The arithmetic mean is taken (drag is linear in density).

Table
-----
:func:`density_table` evaluates this once per activity level on an altitude
grid (100 km to 2000 km every 10 km) and interpolates ``log rho`` linearly
in altitude (the density falls near-exponentially, so this is accurate to
well under 1 % between nodes) and in F10.7 between levels, so that a
solar cycle (F10.7 varying in time) is read from the same table.
"""

from __future__ import annotations

import bisect
import functools
import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.errors import InputShapeError
from casadi_debris.units import M_PER_KM

# The grid the table is built on [km].
ALTITUDE_MIN_KM = 100.0
ALTITUDE_MAX_KM = 2000.0
ALTITUDE_STEP_KM = 10.0
# Orbit, day and year samples of the average.
ORBIT_SAMPLES = 18
LOCAL_TIMES = 12
SEASONS = ("2020-03-20T00:00", "2020-06-21T00:00", "2020-09-22T00:00", "2020-12-21T00:00")
# F10.7 levels [sfu] the table holds, for solar cycles and samples between the named levels.
F107_LEVELS = (65.0, 80.0, 100.0, 120.0, 140.0, 170.0, 200.0, 250.0)
# The WGS-84 ellipsoid (NIMA TR8350.2, 3rd ed., table 3.1): semi-major axis [m], flattening.
WGS84_A_M = 6378137.0
WGS84_F = 1.0 / 298.257223563
LATITUDE_BAND_KM = 500.0
"""Heights h of one NRLMSIS grid call share the geodetic latitude at the band's middle."""


@dataclass(frozen=True)
class SolarActivity:
    """The indices NRLMSIS reads, held constant.

    Attributes
    ----------
    name : str
    f107_sfu : float
        Daily F10.7 (of the previous day) [sfu].
    f107a_sfu : float
        81-day centred mean of F10.7 [sfu].
    ap : float
        Daily planetary geomagnetic index Ap.
    """

    name: str
    f107_sfu: float
    f107a_sfu: float
    ap: float


SOLAR_CASES: dict[str, SolarActivity] = {
    "low": SolarActivity("low", 65.0, 65.0, 0.0),
    "mean": SolarActivity("mean", 140.0, 140.0, 15.0),
    "high": SolarActivity("high", 250.0, 250.0, 45.0),
}
"""The long-term levels of ECSS-E-ST-10-04C, Table 6-3."""


def solar_case(name: str) -> SolarActivity:
    """One of :data:`SOLAR_CASES` by name; an unknown name is an :class:`InputShapeError`."""
    if name not in SOLAR_CASES:
        raise InputShapeError(f"solar activity: one of {', '.join(SOLAR_CASES)}, got {name!r}")
    return SOLAR_CASES[name]


def ap_for_f107(f107_sfu: float) -> float:
    """Ap that goes with an F10.7 level: linear between the named levels' (0, 15, 45).

    Geomagnetic activity rises with solar activity on average; this keeps the
    intermediate levels of the table consistent with the three named ones.
    """
    levels = sorted(SOLAR_CASES.values(), key=lambda case: case.f107_sfu)
    return float(np.interp(f107_sfu, [c.f107_sfu for c in levels], [c.ap for c in levels]))


def geodetic_from_geocentric(
    radius_m: np.ndarray | float, latitude_rad: np.ndarray | float
) -> tuple[np.ndarray, np.ndarray]:
    """Geodetic latitude [rad] and altitude [m] on WGS-84 of a point given in geocentric terms.

    Parameters
    ----------
    radius_m : ndarray or float
        Distance from the Earth's centre [m].
    latitude_rad : ndarray or float
        Geocentric latitude [rad]; broadcast against ``radius_m``.

    Returns
    -------
    latitude_rad, altitude_m : ndarray
        Of the foot of the normal to the ellipsoid through the point, and the height
        along it. By the fixed-point iteration on the latitude (Bowring's form,
        ``tan phi = z / (p (1 - e^2 N / (N + h)))``), to 1e-12 rad.
    """
    r, geocentric = np.broadcast_arrays(
        np.asarray(radius_m, dtype=float), np.asarray(latitude_rad, dtype=float)
    )
    p, z = r * np.cos(geocentric), r * np.sin(geocentric)
    e2 = WGS84_F * (2.0 - WGS84_F)
    latitude = np.arctan2(z, p * (1.0 - e2))
    for _ in range(20):
        sin = np.sin(latitude)
        n = WGS84_A_M / np.sqrt(1.0 - e2 * sin * sin)
        # The height along the normal, well conditioned at every latitude (no 1/cos).
        height = p * np.cos(latitude) + (z + e2 * n * sin) * sin - n
        updated = np.arctan2(z, p * (1.0 - e2 * n / (n + height)))
        done = bool(np.all(np.abs(updated - latitude) < 1e-12))
        latitude = updated
        if done:
            break
    sin = np.sin(latitude)
    n = WGS84_A_M / np.sqrt(1.0 - e2 * sin * sin)
    height = p * np.cos(latitude) + (z + e2 * n * sin) * sin - n
    return latitude, height


def msis_mean_density(
    altitudes_km: np.ndarray,
    activity: SolarActivity,
    inclination_deg: float,
    radius_km: float = WGS84_A_M / M_PER_KM,
) -> np.ndarray:
    """Orbit-, day- and year-averaged NRLMSIS 2.1 mass density [kg/m^3], shape of altitudes.

    Parameters
    ----------
    altitudes_km : ndarray, shape (n,)
        Distance from the Earth's centre less ``radius_km`` [km] (not the height above
        the ground, which varies over the orbit).
    activity : SolarActivity
        Passed to NRLMSIS explicitly (no look-up, no download).
    inclination_deg : float
        Of the orbit: sets the latitudes it spends its time at.
    radius_km : float
        The Earth's equatorial radius as the decay model takes it [km].
    """
    # Imported here: it loads a Fortran library. pymsis ships no type information.
    from pymsis import msis  # type: ignore[import-untyped]

    heights = np.asarray(altitudes_km, dtype=float)
    u = (np.arange(ORBIT_SAMPLES) + 0.5) / ORBIT_SAMPLES * math.pi - math.pi / 2
    geocentric = np.arcsin(math.sin(math.radians(inclination_deg)) * np.sin(u))
    longitudes = np.arange(LOCAL_TIMES) * 360.0 / LOCAL_TIMES
    dates = np.array(SEASONS, dtype="datetime64[m]")
    # Bands fixed in h (not by the heights asked), so that a height's density is the same
    # whatever else is asked with it.
    bands = np.floor(heights / LATITUDE_BAND_KM)
    pieces = []  # (heights' indices, geodetic latitude [deg], geodetic altitudes [km])
    for band in np.unique(bands):
        members = np.flatnonzero(bands == band)
        middle_m = (radius_km + (band + 0.5) * LATITUDE_BAND_KM) * M_PER_KM
        for latitude in geocentric:
            geodetic_lat, _ = geodetic_from_geocentric(middle_m, latitude)
            _, altitude_m = geodetic_from_geocentric(
                (radius_km + heights[members]) * M_PER_KM, latitude
            )
            pieces.append((members, float(np.degrees(geodetic_lat)), altitude_m / M_PER_KM))
    # One fly-through call, ordered so that the altitude varies fastest: NRLMSIS recomputes
    # its horizontal terms only when the date, longitude or latitude changes.
    date_index, lon_index = np.meshgrid(
        np.arange(len(dates)), np.arange(LOCAL_TIMES), indexing="ij"
    )
    per_site = date_index.size
    site_dates = np.repeat(dates[date_index.ravel()], 1)
    site_lons = longitudes[lon_index.ravel()]
    point_dates, point_lons, point_lats, point_alts = [], [], [], []
    for members, lat, alts in pieces:
        point_dates.append(np.repeat(site_dates, members.size))
        point_lons.append(np.repeat(site_lons, members.size))
        point_lats.append(np.full(per_site * members.size, lat))
        point_alts.append(np.tile(alts, per_site))
    n = sum(per_site * members.size for members, _, _ in pieces)
    output = msis.calculate(
        np.concatenate(point_dates),
        np.concatenate(point_lons),
        np.concatenate(point_lats),
        np.concatenate(point_alts),
        f107s=np.full(n, activity.f107_sfu),
        f107as=np.full(n, activity.f107a_sfu),
        aps=np.full((n, 7), activity.ap),
        version=2.1,
    )
    # pymsis answers in single precision: average in double, so that a height's mean does
    # not depend on the shape of the call it came in.
    density = np.asarray(output[:, msis.Variable.MASS_DENSITY], dtype=float)
    total = np.zeros(heights.shape)
    start = 0
    for members, _, _ in pieces:
        size = per_site * members.size
        total[members] += density[start : start + size].reshape(per_site, members.size).mean(axis=0)
        start += size
    return np.asarray(total / geocentric.size, dtype=float)


@dataclass(frozen=True, eq=False)
class DensityTable:
    """``log rho`` on an altitude grid for a set of F10.7 levels.

    Attributes
    ----------
    altitudes_m : ndarray, shape (n,)
        Distance from the Earth's centre less ``radius_m`` [m].
    f107_sfu : ndarray, shape (k,)
        Increasing.
    log_density : ndarray, shape (k, n)
        Natural log of the averaged density [kg/m^3].
    inclination_deg : float
    radius_m : float
        The equatorial radius the altitudes are counted from.
    """

    altitudes_m: np.ndarray
    f107_sfu: np.ndarray
    log_density: np.ndarray
    inclination_deg: float
    radius_m: float = WGS84_A_M

    def profile(self, f107_sfu: float) -> np.ndarray:
        """``log rho`` on the altitude grid at one F10.7 (linear between levels), shape (n,)."""
        levels = self.f107_sfu
        f = min(max(float(f107_sfu), float(levels[0])), float(levels[-1]))
        upper = min(max(bisect.bisect_left(levels.tolist(), f), 1), len(levels) - 1)
        low, high = float(levels[upper - 1]), float(levels[upper])
        weight = (f - low) / (high - low)
        rows = self.log_density
        return rows[upper - 1] + weight * (rows[upper] - rows[upper - 1])

    def density(self, altitude_m: np.ndarray | float, f107_sfu: float) -> np.ndarray:
        """Density [kg/m^3] at altitudes (any shape); log-linear, flat-extrapolated in log slope.

        Below the grid the lowest scale height continues (down to the ground); above it,
        the highest.
        """
        altitude = np.maximum(np.asarray(altitude_m, dtype=float), 0.0)
        return np.exp(log_interp(self.altitudes_m, self.profile(f107_sfu), altitude))


def log_interp(grid: np.ndarray, values: np.ndarray, x: np.ndarray | float) -> np.ndarray:
    """Linear interpolation of ``values`` on ``grid``, continued linearly past both ends."""
    x = np.asarray(x, dtype=float)
    inside = np.interp(x, grid, values)
    if x.min() >= grid[0] and x.max() <= grid[-1]:  # the usual case, kept cheap
        return inside
    low_slope = (values[1] - values[0]) / (grid[1] - grid[0])
    high_slope = (values[-1] - values[-2]) / (grid[-1] - grid[-2])
    below = values[0] + low_slope * (x - grid[0])
    above = values[-1] + high_slope * (x - grid[-1])
    return np.where(x < grid[0], below, np.where(x > grid[-1], above, inside))


@functools.lru_cache(maxsize=8)
def density_table(
    inclination_deg: float,
    levels: tuple[float, ...] = F107_LEVELS,
    radius_m: float = WGS84_A_M,
) -> DensityTable:
    """The averaged NRLMSIS density on the altitude grid at each F10.7 level (cached).

    Each level uses F10.7 = F10.7a and :func:`ap_for_f107`; the named cases
    (65, 140, 250 sfu) are levels of the default table, so they are read
    exactly, not interpolated.

    Parameters
    ----------
    inclination_deg : float
    levels : tuple of float
        Increasing F10.7 levels [sfu].
    radius_m : float
        The Earth's equatorial radius the decay model counts altitudes from
        (``r - radius_m``) [m]; the positions are placed on WGS-84 from it.
    """
    altitudes_km = np.arange(ALTITUDE_MIN_KM, ALTITUDE_MAX_KM + 0.5, ALTITUDE_STEP_KM)
    rows = [
        np.log(
            msis_mean_density(
                altitudes_km,
                SolarActivity(f"{f:g}", f, f, ap_for_f107(f)),
                inclination_deg,
                radius_m / M_PER_KM,
            )
        )
        for f in levels
    ]
    return DensityTable(
        altitudes_m=altitudes_km * M_PER_KM,
        f107_sfu=np.asarray(levels, dtype=float),
        log_density=np.array(rows),
        inclination_deg=float(inclination_deg),
        radius_m=float(radius_m),
    )
