"""The FMU's variables and its ``modelDescription.xml`` (FMI 2.0 co-simulation).

Every variable is a ``Real``; its value reference is its position in
:attr:`FmuLayout.variables`, which is also its index in the C wrapper's value
array. In that order:

- the model's parameters (``inertia_scale_x`` ... ``bending_frequency_scale``,
  the names and meaning of :class:`casadi_debris.dynamics.ParameterLayout`),
  then the initial attitude and rate, then the largest internal step: all
  ``parameter``/``fixed``, set before initialisation;
- the inputs: each engine's thrust [N] (``thrust_cs01_e1_N``, CubeSat and
  engine numbered from 1) and the disturbance torque in B [N m];
- the outputs: the model's state in its own order (attitude ``q_BN`` scalar
  first, body rate, velocity of the undeformed CoG, modal coordinates and
  rates, star-tracker quaternion), then the torque and force the engines apply.
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

import numpy as np

from casadi_debris.dynamics import Model

# The units the variables use, as FMI 2.0 base-unit exponents.
UNITS: dict[str, dict[str, int]] = {
    "N": {"kg": 1, "m": 1, "s": -2},
    "N.m": {"kg": 1, "m": 2, "s": -2},
    "kg": {"kg": 1},
    "m/s": {"m": 1, "s": -1},
    "rad": {"rad": 1},
    "rad/s": {"rad": 1, "s": -1},
    "s": {"s": 1},
}
AXES = ("x", "y", "z")


@dataclass(frozen=True)
class FmuVariable:
    """One scalar variable of the FMU.

    Attributes
    ----------
    name : str
    causality : {"parameter", "input", "output"}
    description : str
    unit : str or None
        One of :data:`UNITS`, or None (dimensionless or not expressible in
        FMI's integer base-unit exponents, e.g. a modal coordinate in kg^0.5 m).
    start : float or None
        Start value (parameters and inputs); None for outputs.
    """

    name: str
    causality: str
    description: str
    unit: str | None = None
    start: float | None = None


@dataclass(frozen=True)
class FmuLayout:
    """The variables of one model's FMU and where each group starts.

    Attributes
    ----------
    variables : tuple of FmuVariable
        Value reference = position.
    n_states, n_engines, n_parameters : int
    """

    variables: tuple[FmuVariable, ...]
    n_states: int
    n_engines: int
    n_parameters: int

    @property
    def initial_attitude(self) -> int:
        """Value reference of ``initial_q0_BN`` (then q1..q3, then the three rates)."""
        return self.n_parameters

    @property
    def max_step(self) -> int:
        """Value reference of ``max_step_s``."""
        return self.n_parameters + 7

    @property
    def thrust(self) -> int:
        """Value reference of the first engine's thrust."""
        return self.max_step + 1

    @property
    def disturbance(self) -> int:
        """Value reference of ``disturbance_x_Nm``."""
        return self.thrust + self.n_engines

    @property
    def state(self) -> int:
        """Value reference of the first state output (``q0_BN``)."""
        return self.disturbance + 3

    @property
    def torque(self) -> int:
        """Value reference of ``torque_x_Nm`` (then y, z, then the force)."""
        return self.state + self.n_states

    @property
    def size(self) -> int:
        """Number of variables."""
        return len(self.variables)

    def reference(self, name: str) -> int:
        """Value reference of the variable ``name``."""
        for index, variable in enumerate(self.variables):
            if variable.name == name:
                return index
        raise KeyError(name)

    def names(self, causality: str) -> tuple[str, ...]:
        """Names of the variables of one causality, in value-reference order."""
        return tuple(v.name for v in self.variables if v.causality == causality)


def engine_names(model: Model) -> tuple[str, ...]:
    """The thrust inputs' names, ``thrust_cs01_e1_N``: CubeSat and engine (in it) from 1."""
    cubesats = model.geometry.cubesats
    width = max(2, len(str(len(cubesats))))
    names = []
    for engine in model.geometry.engines:
        within = cubesats[engine.cubesat].engines.index(engine.index) + 1
        names.append(f"thrust_cs{engine.cubesat + 1:0{width}d}_e{within}_N")
    return tuple(names)


def fmu_layout(model: Model, max_step_s: float) -> FmuLayout:
    """All variables of the FMU of ``model``, with the model's nominal parameters as start values.

    Parameters
    ----------
    model : Model
    max_step_s : float
        Start value of the ``max_step_s`` parameter [s].
    """
    parameters = [
        FmuVariable(
            name, "parameter", _PARAMETER_TEXT[_base(name)], _PARAMETER_UNIT[_base(name)], v
        )
        for name, v in model.nominal.items()
    ]
    initial = [
        FmuVariable(
            f"initial_q{i}_BN",
            "parameter",
            f"initial attitude q_BN, component {i} (scalar first; normalised at initialisation)",
            None,
            1.0 if i == 0 else 0.0,
        )
        for i in range(4)
    ] + [
        FmuVariable(
            f"initial_omega_{a}_rad_s", "parameter", f"initial body rate about {a}_B", "rad/s", 0.0
        )
        for a in AXES
    ]
    step = FmuVariable(
        "max_step_s",
        "parameter",
        "largest internal RK4 step; each communication step is cut into equal sub-steps "
        "no longer than this",
        "s",
        max_step_s,
    )
    return FmuLayout(
        variables=(
            *parameters, *initial, step, *_inputs(model), *_state_outputs(model), *_load_outputs()
        ),
        n_states=model.layout.size,
        n_engines=len(model.geometry.engines),
        n_parameters=len(parameters),
    )  # fmt: skip


_PARAMETER_TEXT = {
    "inertia_scale": "factor on the hub-and-CubeSats inertia about this axis (1 nominal)",
    "mass_kg": "total mass",
    "array_angle_offset_rad": "turn of the array(s) about the hinge axis from the nominal angle",
    "bending_frequency_scale": "factor on every array's first bending frequency (1 nominal)",
}
_PARAMETER_UNIT: dict[str, str | None] = {
    "inertia_scale": None,
    "mass_kg": "kg",
    "array_angle_offset_rad": "rad",
    "bending_frequency_scale": None,
}


def _base(name: str) -> str:
    """The family of a model parameter's name (``array2_angle_offset_rad`` -> the angle)."""
    if name.startswith("inertia_scale"):
        return "inertia_scale"
    return re.sub(r"^array\d+_", "array_", name)


def _inputs(model: Model) -> list[FmuVariable]:
    inputs = []
    for name, engine in zip(engine_names(model), model.geometry.engines, strict=True):
        direction = np.array2string(engine.direction, precision=4, separator=", ")
        position = np.array2string(engine.position_m, precision=4, separator=", ")
        inputs.append(
            FmuVariable(
                name,
                "input",
                f"engine thrust, held over each communication step and limited to "
                f"[0, {engine.max_thrust_N:.6g}] N; force along {direction} in B at "
                f"{position} m from the CoG",
                "N",
                0.0,
            )
        )
    inputs += [
        FmuVariable(f"disturbance_{a}_Nm", "input", f"external torque about {a}_B", "N.m", 0.0)
        for a in AXES
    ]
    return inputs


def _state_outputs(model: Model) -> list[FmuVariable]:
    layout = model.layout
    modal = [f"array{a}_{m}" for a, m in layout.mode_labels]
    outputs = [
        FmuVariable(
            f"q{i}_BN", "output", f"attitude of B in N, quaternion component {i} (scalar first)"
        )
        for i in range(4)
    ]
    outputs += [
        FmuVariable(f"omega_{a}_rad_s", "output", f"body rate omega_BN about {a}_B", "rad/s")
        for a in AXES
    ]
    outputs += [
        FmuVariable(f"v_{a}_m_s", "output", f"velocity of the undeformed CoG along {a}_B", "m/s")
        for a in AXES
    ]
    outputs += [
        FmuVariable(f"eta_{n}", "output", f"modal coordinate of {n} (mass-normalised, kg^0.5 m)")
        for n in modal
    ]
    outputs += [
        FmuVariable(f"eta_dot_{n}", "output", f"modal rate of {n} (mass-normalised, kg^0.5 m/s)")
        for n in modal
    ]
    outputs += [
        FmuVariable(f"q{i}_ST", "output", f"star-tracker attitude (first-order low pass of q_BN), "
                    f"component {i}")
        for i in range(4)
    ]  # fmt: skip
    return outputs


def _load_outputs() -> list[FmuVariable]:
    return [
        FmuVariable(f"torque_{a}_Nm", "output", f"torque of the engines about {a}_B (thrust "
                    "as limited)", "N.m")
        for a in AXES
    ] + [
        FmuVariable(f"force_{a}_N", "output", f"force of the engines along {a}_B (thrust "
                    "as limited)", "N")
        for a in AXES
    ]  # fmt: skip


@dataclass(frozen=True)
class Description:
    """What the model description names besides the variables."""

    model_name: str
    model_identifier: str
    description: str
    generation_tool: str
    source_files: tuple[str, ...]
    stop_time_s: float
    step_size_s: float


def model_description(layout: FmuLayout, about: Description) -> tuple[str, str]:
    """``modelDescription.xml`` of the FMU and its GUID, a hash of everything else in it."""
    body = _description_body(layout, about)
    guid = guid_of(body)
    return body.replace('guid="{}"', f'guid="{guid}"', 1), guid


def guid_of(text: str) -> str:
    """A GUID-shaped digest of ``text``: the same description always has the same GUID."""
    digest = hashlib.sha256(text.encode()).hexdigest()
    return f"{{{digest[:8]}-{digest[8:12]}-{digest[12:16]}-{digest[16:20]}-{digest[20:32]}}}"


def _description_body(layout: FmuLayout, about: Description) -> str:
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        "<fmiModelDescription",
        '  fmiVersion="2.0"',
        f"  modelName={quoteattr(about.model_name)}",
        '  guid="{}"',
        f"  description={quoteattr(about.description)}",
        f"  generationTool={quoteattr(about.generation_tool)}",
        '  variableNamingConvention="structured"',
        '  numberOfEventIndicators="0">',
        f"  <CoSimulation modelIdentifier={quoteattr(about.model_identifier)}",
        '    canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false"',
        '    maxOutputDerivativeOrder="0" canRunAsynchronuously="false"',
        '    canBeInstantiatedOnlyOncePerProcess="false"',
        '    canNotUseMemoryManagementFunctions="false"',
        '    canGetAndSetFMUstate="true" canSerializeFMUstate="false"',
        '    providesDirectionalDerivative="false">',
        "    <SourceFiles>",
        *(f"      <File name={quoteattr(name)}/>" for name in about.source_files),
        "    </SourceFiles>",
        "  </CoSimulation>",
        "  <UnitDefinitions>",
        *(
            f"    <Unit name={quoteattr(unit)}><BaseUnit "
            + " ".join(f'{k}="{v}"' for k, v in exponents.items())
            + "/></Unit>"
            for unit, exponents in sorted(UNITS.items())
        ),
        "  </UnitDefinitions>",
        "  <LogCategories>",
        '    <Category name="logStatusError" description="errors: bad values, failed steps"/>',
        "  </LogCategories>",
        f'  <DefaultExperiment startTime="0" stopTime="{about.stop_time_s!r}" '
        f'stepSize="{about.step_size_s!r}"/>',
        "  <ModelVariables>",
        *(_scalar_variable(index, v) for index, v in enumerate(layout.variables)),
        "  </ModelVariables>",
        *_model_structure(layout),
        "</fmiModelDescription>",
    ]
    return "\n".join(lines) + "\n"


def _scalar_variable(reference: int, variable: FmuVariable) -> str:
    attributes = [
        f"name={quoteattr(variable.name)}",
        f'valueReference="{reference}"',
        f"description={quoteattr(variable.description)}",
        f'causality="{variable.causality}"',
    ]
    if variable.causality == "parameter":
        attributes += ['variability="fixed"', 'initial="exact"']
    else:
        attributes.append('variability="continuous"')
    real = []
    if variable.start is not None:
        real.append(f'start="{float(variable.start)!r}"')
    if variable.unit is not None:
        real.append(f"unit={quoteattr(variable.unit)}")
    return (
        f"    <ScalarVariable {' '.join(attributes)}>"
        f"<Real{''.join(' ' + a for a in real)}/></ScalarVariable>"
        f"  <!-- index {reference + 1} -->"
    )


def _model_structure(layout: FmuLayout) -> list[str]:
    """Outputs: the state depends on no input within a step; the loads on the thrusts only."""
    thrusts = " ".join(str(layout.thrust + k + 1) for k in range(layout.n_engines))
    outputs = [
        index for index, v in enumerate(layout.variables, start=1) if v.causality == "output"
    ]
    lines = ["  <ModelStructure>", "    <Outputs>"]
    for index in outputs:
        loads = index - 1 >= layout.torque
        dependencies = thrusts if loads else ""
        kinds = " ".join(["dependent"] * layout.n_engines) if loads else ""
        lines.append(
            f'      <Unknown index="{index}" dependencies="{dependencies}" '
            f'dependenciesKind="{kinds}"/>'
        )
    lines += ["    </Outputs>", "    <InitialUnknowns>"]
    lines += [f'      <Unknown index="{index}"/>' for index in outputs]
    lines += ["    </InitialUnknowns>", "  </ModelStructure>"]
    return lines
