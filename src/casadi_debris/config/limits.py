"""The range of every number in a problem file, and the reasons for each.

Every number a problem file gives has a lower and an upper bound, so that a
typo (``1e9`` for ``1e-9``), an overflow (``1e308``) or an unphysical value is
refused at load time with the key named, instead of hanging a simulation or
reaching the model as NaN. The bounds are wide on purpose: they bound what is
physically meaningful for a satellite and its docked CubeSats, not what the
paper uses. Units are those of the key (SI unless the key says otherwise).

Other layers may use these constants to bound their own inputs the same way
(e.g. a command-line sample count against :data:`MONTECARLO_SAMPLES`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Range:
    """An interval of allowed values, closed unless told open.

    Attributes
    ----------
    low, high : float
        Bounds, in the unit of the key.
    low_open, high_open : bool
        Whether the bound itself is excluded.
    """

    low: float
    high: float
    low_open: bool = False
    high_open: bool = False

    def __str__(self) -> str:
        left = "(" if self.low_open else "["
        right = ")" if self.high_open else "]"
        return f"{left}{_show(self.low)}, {_show(self.high)}{right}"

    def violation(self, values: np.ndarray | float) -> str | None:
        """What is wrong with ``values`` (all must lie inside), or None.

        Parameters
        ----------
        values : ndarray or float
            Finite values.

        Returns
        -------
        str or None
            E.g. ``"must be positive"`` or ``"must be at most 1000"``.
        """
        array = np.asarray(values, dtype=float)
        low, high = _show(self.low), _show(self.high)
        if self.low_open and np.any(array <= self.low):
            return "must be positive" if self.low == 0 else f"must be above {low}"
        if not self.low_open and np.any(array < self.low):
            if self.low == 0:
                return "must not be negative"
            if self.low > 0 and np.any(array <= 0):
                return f"must be positive (at least {low})"
            return f"must be at least {low}"
        if self.high_open and np.any(array >= self.high):
            return f"must be below {high}"
        if not self.high_open and np.any(array > self.high):
            return f"must be at most {high}"
        return None


def _show(bound: float) -> str:
    """A bound as written in a message: integers whole (4294967295), floats short (1e+06)."""
    return str(bound) if isinstance(bound, int) else f"{bound:g}"


def positive(high: float) -> Range:
    """The range (0, high]."""
    return Range(0.0, high, low_open=True)


def nonnegative(high: float) -> Range:
    """The range [0, high]."""
    return Range(0.0, high)


def symmetric(bound: float) -> Range:
    """The range [-bound, bound]."""
    return Range(-bound, bound)


FRACTION_BELOW_ONE = Range(0.0, 1.0, high_open=True)
"""[0, 1): relative half-ranges, damping ratios, edge insets."""
SMALL_GAIN = Range(1e-6, 1.0, high_open=True)
"""[1e-6, 1): the weights' epsilon and high-frequency gain (the paper: 0.001, 0.01); below 1e-6
the weights are integrators and differentiators in all but name and the synthesis is singular."""

# ------------------------------------------------------------------ bodies
MASS_KG = Range(1e-3, 1e6)
"""[1 g, 1e6 kg] for the hub and each array: the ISS, the largest object in orbit, is 4.2e5 kg."""
CUBESAT_MASS_KG = Range(1e-3, 1e3)
"""[1 g, 1000 kg] per docked CubeSat: a 27U CubeSat is about 40 kg; this allows any servicer."""
HUB_SIZE_M = Range(0.01, 200.0)
"""[0.01, 200] m per hub edge: CubeSats dock on its faces (not a point); the ISS truss is 109 m."""
LENGTH_M = Range(1e-3, 200.0)
"""[1 mm, 200 m]: array length and width; the ISS truss is 109 m."""
STANDOFF_M = Range(0.0, 200.0)
"""[0, 200] m: height of a CubeSat's centre of gravity above its face."""
POSITION_M = nonnegative(200.0)
"""[0, 200] m: points in the hub-corner frame (then checked against the hub's own size)."""
CUBESAT_POSITION_M = symmetric(400.0)
"""|x| <= 400 m per axis: a CubeSat's CoG in the hub-corner frame (outside the hub, so it may
lie below 0 on the -x, -y, -z faces)."""
INERTIA_KGM2 = symmetric(1e9)
"""|I_ij| <= 1e9 kg m^2: the ISS is about 1e8 kg m^2; then checked positive definite."""
PRINCIPAL_INERTIA_KGM2 = Range(1e-6, 1e9)
"""[1e-6, 1e9] kg m^2: principal moments of any body (a 1U CubeSat: 2e-3 kg m^2); smaller ones
make the model's inverse inertia overflow."""
ANGLE_DEG = symmetric(360.0)
"""[-360, 360] deg: an array angle or a phase; any attitude is reachable within one turn."""
MODE_OMEGA_RAD_S = Range(1e-3, 1e4)
"""[0.001, 1e4] rad/s: a 'mode' slower than one cycle in 100 min is rigid motion, not vibration."""
MODE_ORDER = Range(1, 6)
"""Mode order 1 to 6: the model tabulates the cantilever shapes up to the sixth."""
MAX_ARRAYS = 16
"""At most 16 arrays (hinges): each adds its modes' states to the model."""
MAX_MODES = 16
"""At most 16 modes per array: each adds two states per array to the model."""
MAX_CUBESATS = 256
"""At most 256 docked CubeSats: each engine is a column of the allocator's QP, solved every
control period."""
MAX_ENGINES_PER_CUBESAT = 16
"""At most 16 engines per CubeSat (a 2U with differential firing has a handful)."""
MAX_ENGINES = 512
"""At most 512 engines in all: the allocator's QP grows with every one."""
OFFSET_M = symmetric(10.0)
"""|offset| <= 10 m per axis: an engine point relative to its CubeSat's centre of gravity."""
DIRECTION = symmetric(1e3)
"""|component| <= 1000 for a direction vector (then normalised; it must not be zero)."""
POINTING_ARCSEC = Range(1e-3, 1e6)
"""[0.001, 1e6] arcsec: a pointing requirement (the paper: 60)."""
SLEW_ERROR_DEG = Range(1e-6, 180.0)
"""[1e-6, 180] deg: the largest attitude error allowed during a slew (the paper: 0.6)."""

# ------------------------------------------------------------------ engines
STAGES = Range(1, 16)
"""1 to 16 iESE stages per engine (the paper: 3)."""
EMITTERS_PER_STAGE = Range(1, 10_000)
"""1 to 10 000 emitters per stage (the paper: 32)."""
THRUST_MN = Range(1e-6, 1e4)
"""[1e-6, 1e4] mN per stage (1 nN to 10 N): electrosprays give 0.01 to 1 mN, cold gas 10 N."""
ISP_S = Range(1.0, 1e5)
"""[1, 1e5] s: cold gas gives 50 s, gridded ion engines reach 1e4 s."""
STAGE_LIFE_H = Range(1e-3, 1e6)
"""[3.6 s, 1e6 h] per stage (114 years); the propellant check (below the CubeSat's mass) binds
first."""

# ------------------------------------------------------------------ environment and control
DISTURBANCE_MNM = nonnegative(1e6)
"""[0, 1e6] mNm (1 kN m): environmental torques on a 1 t satellite are below 1 mNm."""
DISTURBANCE_PERIOD_MIN = Range(1.0, 1e6)
"""[1, 1e6] min: orbital disturbances repeat once or twice per orbit (>= 87 min in LEO)."""
BANDWIDTH_RAD_S = Range(1e-6, 1e4)
"""[1e-6, 1e4] rad/s: star tracker and weight bandwidths (the paper: 0.028 to 50 rad/s); the
integration-step check binds below the upper bound."""
SCALING = Range(1e-6, 1e6)
"""[1e-6, 1e6] deg or mNm: the weights' scalings (the paper's: 0.002 deg to 4.6 mNm)."""
RATE_RAD_S = symmetric(10.0)
"""|w| <= 10 rad/s initial tumble (95 rpm): Envisat turns at 0.05 rad/s; the paper uses 1."""
ALTITUDE_KM = Range(100.0, 1e5)
"""[100, 1e5] km: below 100 km no orbit lasts a revolution; 1e5 km is beyond GEO."""
INCLINATION_DEG = Range(0.0, 180.0)
"""[0, 180] deg: the definition of an inclination."""
EARTH_MU_KM3_S2 = Range(394_600.0, 402_600.0)
"""398 600 km^3/s^2 +-1 %: every Earth model agrees to 1e-9; the keys are the Earth's."""
EARTH_RADIUS_KM = Range(6_300.0, 6_450.0)
"""[6300, 6450] km: the polar (6357), mean (6371) and equatorial (6378) radii, +-1 %."""
STANDARD_GRAVITY_M_S2 = Range(9.7, 9.9)
"""[9.7, 9.9] m/s^2: 9.80665 by definition, local gravity 9.78 to 9.83."""
DENSITY_KG_M3 = Range(0.0, 1e-6)
"""[0, 1e-6] kg/m^3: the air density along the orbit, from 0 (no drag) to 1e-6 (about 150 km,
where nothing stays a revolution); at 685 km it lies between 1e-14 and 1e-12."""
DRAG_COEFFICIENT = Range(0.5, 5.0)
"""[0.5, 5] for C_D: free-molecular flat plates lie between 2 and 3 (2.2 usual)."""
REFLECTIVITY = Range(0.0, 1.0)
"""[0, 1] fractions of the sunlight reflected specularly or diffusely (their sum at most 1)."""
SOLAR_PRESSURE_N_M2 = Range(0.0, 1e-4)
"""[0, 1e-4] N/m^2: 4.56e-6 at 1 AU; 1e-4 is inside Mercury's orbit."""
RESIDUAL_DIPOLE_AM2 = symmetric(1e3)
"""|m| <= 1000 A m^2 per axis: a satellite's residual dipole is 0.01 to 10 A m^2."""
DIPOLE_TILT_DEG = Range(0.0, 180.0)
"""[0, 180] deg: the colatitude of the dipole's north pole (9.4 deg for the Earth in 2020)."""
FIELD_T = Range(0.0, 1e-3)
"""[0, 1e-3] T: the dipole field at the equator's surface (Earth: 3.0e-5 T)."""
UNCERTAINTY_ANGLE_DEG = Range(0.0, 180.0)
"""[0, 180] deg half-range of the array angle: 180 covers every angle."""
UNCERTAINTY_SAMPLES = Range(1, 10_000)
"""1 to 10 000 models for the uncertainty-weight fit: each keeps a 3x3 complex response on
the fitting grid (about 0.26 MB at 1800 frequencies), 2.6 GB at the bound (the paper: 200)."""
SEED = Range(0, 2**32 - 1)
"""Seeds are unsigned 32-bit integers, as every random generator and file format stores them."""

# ------------------------------------------------------------------ simulation and campaigns
DURATION_S = positive(1e7)
"""(0, 1e7] s (116 days): simulated time, slew duration and start, failure times."""
SLEW_ANGLE_DEG = Range(1e-6, 180.0)
"""[1e-6, 180] deg: a slew turns the short way (180 at most); 1e-6 deg (0.004 arcsec) is far below
any star tracker, and smaller angles vanish in radians."""
SLEW_DURATION_S = Range(1.0, 1e7)
"""[1 s, 1e7 s]: no thruster turns a satellite round in under a second; the slew methods then
check the duration against the minimum the engines allow."""
MAX_SEGMENTS = 100
"""At most 100 segments in a run's manoeuvre: each slew among them is solved on its own."""
AXIS_COMPONENT = symmetric(1e6)
"""|a| <= 1e6 per component of an axis vector (normalised where used; zero refused)."""
AXIS_PARALLEL_TOLERANCE = 1e-6
"""Two unit axes closer to parallel than this (sine of their angle) define no frame."""
QUATERNION_COMPONENT = symmetric(2.0)
"""|q_i| <= 2 per component of a quaternion as written (then checked for unit norm)."""
QUATERNION_NORM_TOLERANCE = 1e-3
"""A written quaternion's norm within 1e-3 of 1 (four decimals suffice), then normalised; a
typo or a rate [0, omega] is refused."""
BLEND_S = Range(1.0, 1e5)
"""[1 s, 1e5 s]: the time a reference at a new rate takes to be joined (a track's start)."""
CONTROL_RATE_HZ = Range(0.01, 1000.0)
"""[0.01, 1000] Hz: one control period between 1 ms and 100 s (the paper: 10 Hz)."""
INTEGRATOR_STEPS = Range(1, 1000)
"""1 to 1000 Runge-Kutta steps per control period (the paper: 4)."""
MAX_CONTROL_PERIODS = 1_000_000
"""duration_s x control_rate_hz <= 1e6: one day at 10 Hz is 864 000 periods; the run keeps
every period's state and thrust in memory (about 0.5 GB at the bound)."""
MAX_INTEGRATION_STEPS = 10_000_000
"""control periods x integrator_steps <= 1e7: about two minutes at the measured 1e5 steps/s
(one day at 10 Hz with 4 steps is 3.5e6)."""
RK4_STABLE_STEP = 2.0
"""Largest h x omega allowed for one Runge-Kutta step of length h: classical RK4 is stable
up to 2.78 on the real axis and 2.83 on the imaginary one; the margin covers the coupled
(free-free) frequencies, which lie above the cantilevered ones the file gives."""
MAX_FAILURES = 1000
"""At most 1000 failure events (the paper's 24 CubeSats x 3 stages have 96 to lose)."""
CORNER_ARRAY_ANGLES = Range(1, 64)
"""1 to 64 array angles in the corner set: 2^5 x 64 = 2048 corner cases (the paper: 8, 256)."""
MAX_CORNER_CASES = 4096
"""At most 4096 corner cases (with one angle per array, corner_array_angles^n_arrays x 2^5):
a corner campaign of the paper's slew takes about 2 s a case on two cores, 2 h for 4096."""
MAX_VARIED_QUANTITIES = 64
"""At most 64 quantities varied by a campaign (``[[montecarlo.vary]]``)."""
MAX_VARIED_CORNERS = 12
"""At most 12 of them with ``corners``: 2^12 = 4096 combinations (:data:`MAX_CORNER_CASES`)."""
VARIED_VALUE = Range(-1e12, 1e12)
"""Bounds, mean and sigma of a varied quantity before its key's own range is checked."""
MONTECARLO_SAMPLES = Range(1, 100_000)
"""1 to 100 000 random closed-loop cases: about a day on two cores at one second a case."""

# ------------------------------------------------------------------ synthesis and analysis
MU_POINTS = Range(10, 5000)
"""Frequencies of the mu grid: below 10 the peak is missed; each point costs an SVD per D fit."""
D_ORDER = Range(0, 8)
"""Order of each D-scale fit: a rational fit above order 8 is ill-conditioned on 150 points,
and every order adds two states per channel to the controller."""
MAX_D_ORDERS_TRIED = 6
"""At most 6 D-scale orders tried at each D-K step (each is a whole H-inf synthesis)."""
DK_ITERATIONS = Range(0, 50)
"""D-K steps at most (the paper's design converges in 4 to 8)."""
REDUCED_ORDER = Range(1, 500)
"""Target order of the balanced truncation."""
MARGIN_SAMPLES = Range(1, 100_000)
"""Sampled plants of a margin study: 3000 take about 12 s on two cores (the paper: 3000)."""

# ------------------------------------------------------------------ text and files
NAME_PATTERN = r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}"
"""A problem or mode name is a label (output folders are named after it), not a path: a letter
or digit, then up to 63 letters, digits, '.', '_' or '-'; so never '.', '..' nor a separator."""
MAX_DESCRIPTION_CHARS = 1000
"""A description is prose of at most 1000 characters, without control characters."""
MAX_FILE_BYTES = 1_000_000
"""A problem file (and each file it extends) is at most 1 MB; the paper's is 5 kB."""
MAX_CONTROLLER_BYTES = 16_000_000
"""A controller file is at most 16 MB (the paper's 25-state design with its full-order
controller and weights is 0.2 MB)."""
MAX_TABLE_BYTES = 64_000_000
"""A torque table (``simulate --open-loop``) is at most 64 MB (about a million rows)."""
MAX_EXTENDS_DEPTH = 8
"""At most 8 files in an ``extends`` chain below the one loaded."""
