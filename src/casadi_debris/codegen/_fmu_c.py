"""The C of the FMU: CasADi's code for the plant, and an FMI 2.0 co-simulation wrapper around it.

Two files go to ``sources/``:

- ``plant.c``, written by CasADi's code generator from the model's own
  ``dynamics`` Function: ``cdb_plant(x, thrust, disturbance, p) -> xdot`` (the
  engines' torque and force maps folded in) and ``cdb_loads(thrust) -> (torque,
  force)``;
- ``fmu.c``, the wrapper (it includes ``plant.c``: one translation unit to
  compile). Between communication points it holds the inputs and integrates
  with the classical fourth-order Runge-Kutta method in equal sub-steps no
  longer than the ``max_step_s`` parameter. Memory comes from the importer's
  ``allocateMemory`` only; one instance is one struct.

The wrapper declares the few FMI 2.0 types it needs itself, so that the sources
build with nothing but a C99 compiler; define ``CDB_FMI2_HEADERS`` (and put the
standard's headers on the include path) to compile it against
``fmi2Functions.h`` instead, which checks every signature against the standard.
"""

from __future__ import annotations

from string import Template

import casadi as ca
import numpy as np

from casadi_debris.codegen._fmu_variables import FmuLayout
from casadi_debris.dynamics import Model

PLANT_FILE = "plant.c"
WRAPPER_FILE = "fmu.c"
# Internal names of the generated code get a fixed prefix, not a random one: the same model
# always gives the same C.
CODEGEN_OPTIONS: dict[str, str | bool] = {
    "prefix": "cdb_",
    "with_header": False,
    "casadi_int": "long long int",
}


def plant_functions(model: Model) -> tuple[ca.Function, ca.Function]:
    """``cdb_plant(x, thrust, disturbance, p) -> xdot``, ``cdb_loads(thrust) -> (torque, force)``.

    Thrust [N] per engine, disturbance torque [N m] in B, p laid out as
    ``model.parameter_layout``; torque [N m] and force [N] in B.
    """
    geometry = model.geometry
    n_engines = len(geometry.engines)
    x = ca.SX.sym("x", model.layout.size)
    thrust = ca.SX.sym("thrust", n_engines)
    disturbance = ca.SX.sym("disturbance", 3)
    p = ca.SX.sym("p", len(model.parameter_names))
    torque = ca.DM(geometry.torque_map) @ thrust
    force = ca.DM(geometry.force_map) @ thrust
    xdot = model.dynamics(x, ca.vertcat(torque, disturbance, force), p)
    plant = ca.Function(
        "cdb_plant",
        [x, thrust, disturbance, p],
        [xdot],
        ["x", "thrust", "disturbance", "p"],
        ["xdot"],
    )
    loads = ca.Function("cdb_loads", [thrust], [torque, force], ["thrust"], ["torque", "force"])
    return plant, loads


def plant_source(model: Model) -> tuple[str, dict[str, int]]:
    """The generated C of the plant and the work-array sizes the wrapper reserves."""
    plant, loads = plant_functions(model)
    generator = ca.CodeGenerator("plant", CODEGEN_OPTIONS)
    generator.add(plant)
    generator.add(loads)
    sizes = {
        "SZ_ARG": max(plant.sz_arg(), loads.sz_arg()),
        "SZ_RES": max(plant.sz_res(), loads.sz_res()),
        "SZ_IW": max(plant.sz_iw(), loads.sz_iw(), 1),
        "SZ_W": max(plant.sz_w(), loads.sz_w(), 1),
    }
    return str(generator.dump()), sizes


def wrapper_source(
    model: Model, layout: FmuLayout, sizes: dict[str, int], model_identifier: str, guid: str
) -> str:
    """``fmu.c``: the FMI 2.0 co-simulation functions around the generated plant.

    ``sizes`` are the work-array sizes :func:`plant_source` returns.
    """
    positive = [
        layout.reference(name)
        for name in model.parameter_names
        if name == "mass_kg" or name.startswith("inertia_scale")
    ] + [layout.max_step]
    max_thrust = [engine.max_thrust_N for engine in model.geometry.engines]
    starts = [0.0 if v.start is None else v.start for v in layout.variables]
    values = {
        "IDENTIFIER": model_identifier,
        "GUID": guid,
        "NX": layout.n_states,
        "NE": layout.n_engines,
        "NR": layout.size,
        "VR_INIT": layout.initial_attitude,
        "VR_MAX_STEP": layout.max_step,
        "VR_THRUST": layout.thrust,
        "VR_DIST": layout.disturbance,
        "VR_STATE": layout.state,
        "VR_LOADS": layout.torque,
        "Q_ST": model.layout.q_st.start,
        "N_POSITIVE": len(positive),
        "POSITIVE": ", ".join(map(str, positive)),
        "MAX_THRUST": _c_array(max_thrust or [0.0]),  # C99 has no empty array
        "START": _c_array(starts),
        "NAMES": _c_strings([v.name for v in layout.variables]),
        **sizes,
    }
    return Template(_WRAPPER).substitute(values)


def _c_strings(names: list[str]) -> str:
    """Variable names as C string literals, four a line (they are plain identifiers)."""
    items = [f'"{name}"' for name in names]
    return ",\n    ".join(", ".join(items[i : i + 4]) for i in range(0, len(items), 4))


def _c_array(values: list[float] | np.ndarray) -> str:
    """Doubles in C, exactly (17 significant digits), eight a line."""
    items = [f"{float(v):.17g}" for v in values]
    return ",\n    ".join(", ".join(items[i : i + 8]) for i in range(0, len(items), 8))


_WRAPPER = r"""/* FMI 2.0 co-simulation of the debris model ${IDENTIFIER}, written by casadi_debris.
 *
 * Build (any C99 compiler):  cc -std=c99 -O2 -fPIC -shared -fvisibility=hidden \
 *                                -o ${IDENTIFIER}.so fmu.c -lm
 * The plant (plant.c) is CasADi's C for the model's dynamics Function; this file
 * holds the inputs over each communication step and integrates with RK4 in equal
 * sub-steps of at most max_step_s. Value reference = index into the value array.
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#if defined(__GNUC__)
#define CDB_EXPORT __attribute__((visibility("default")))
#define CASADI_SYMBOL_EXPORT __attribute__((visibility("hidden")))
#else
#define CDB_EXPORT
#define CASADI_SYMBOL_EXPORT
#endif

#ifdef CDB_FMI2_HEADERS
#include "fmi2Functions.h"
#else
typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef char fmi2Byte;
#define fmi2True 1
#define fmi2False 0
#define fmi2TypesPlatform "default"
#define fmi2Version "2.0"
typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum {
    fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime, fmi2Terminated
} fmi2StatusKind;
typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String,
                                   fmi2String, ...);
typedef void *(*fmi2CallbackAllocateMemory)(size_t, size_t);
typedef void (*fmi2CallbackFreeMemory)(void *);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment, fmi2Status);
typedef struct {
    fmi2CallbackLogger logger;
    fmi2CallbackAllocateMemory allocateMemory;
    fmi2CallbackFreeMemory freeMemory;
    fmi2StepFinished stepFinished;
    fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;
#endif

#include "plant.c"

#define GUID "${GUID}"
#define NX ${NX}                 /* states */
#define NE ${NE}                 /* engines */
#define NE_ALLOC (NE > 0 ? NE : 1)
#define NR ${NR}                 /* Real variables */
#define VR_INIT ${VR_INIT}       /* initial q_BN (4), omega (3) */
#define VR_MAX_STEP ${VR_MAX_STEP}
#define VR_THRUST ${VR_THRUST}   /* NE thrusts [N] */
#define VR_DIST ${VR_DIST}       /* disturbance torque [N m] (3) */
#define VR_STATE ${VR_STATE}     /* NX state outputs */
#define VR_LOADS ${VR_LOADS}     /* torque [N m] (3), force [N] (3) */
#define Q_ST ${Q_ST}             /* star-tracker quaternion in the state */
#define N_POSITIVE ${N_POSITIVE}
#define SZ_ARG ${SZ_ARG}
#define SZ_RES ${SZ_RES}
#define SZ_IW ${SZ_IW}
#define SZ_W ${SZ_W}
/* Largest number of sub-steps in one communication step: a guard against a typo in
 * max_step_s, not a limit of the method. */
#define MAX_SUBSTEPS 100000000.0

static const double max_thrust_N[NE_ALLOC] = {
    ${MAX_THRUST}
};
static const double start_values[NR] = {
    ${START}
};
/* Names, for the messages: an error names the variable. */
static const char *const names[NR] = {
    ${NAMES}
};
/* Parameters that must be positive: mass, inertia factors, the step. */
static const int positive[N_POSITIVE] = {${POSITIVE}};

typedef enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED, FAILED } Phase;

typedef struct {
    fmi2CallbackFunctions cb;
    char name[128];
    int logging;
    Phase phase;
    double time;
    double r[NR];
    double x[NX];
    double thrust[NE_ALLOC];
    double k[4][NX];
    double trial[NX];
    const casadi_real *arg[SZ_ARG];
    casadi_real *res[SZ_RES];
    casadi_int iw[SZ_IW];
    casadi_real w[SZ_W];
} Instance;

static void report(Instance *m, fmi2Status status, const char *format, ...) {
    char text[512], *p;
    va_list args;
    if (m == NULL || m->cb.logger == NULL || (!m->logging && status < fmi2Error)) return;
    va_start(args, format);
    vsnprintf(text, sizeof text, format, args);
    va_end(args);
    /* The text goes as the message itself (some importers print it without formatting),
     * so no '%' may be left in it to be read as a conversion by those that do. */
    for (p = text; *p; ++p)
        if (*p == '%') *p = '?';
    m->cb.logger(m->cb.componentEnvironment, m->name, status, "logStatusError", text);
}

static fmi2Status fail(Instance *m, const char *where, const char *what) {
    report(m, fmi2Error, "%s: %s", where, what);
    return fmi2Error;
}

/* The applied thrust: each engine pushes between 0 and its one-stage thrust. */
static void limit_thrust(Instance *m) {
    int e;
    for (e = 0; e < NE; ++e) {
        double u = m->r[VR_THRUST + e];
        m->thrust[e] = u < 0.0 ? 0.0 : (u > max_thrust_N[e] ? max_thrust_N[e] : u);
    }
}

static void rate(Instance *m, const double *x, double *xdot) {
    m->arg[0] = x;
    m->arg[1] = m->thrust;
    m->arg[2] = m->r + VR_DIST;
    m->arg[3] = m->r; /* the model's parameters come first */
    m->res[0] = xdot;
    cdb_plant(m->arg, m->res, m->iw, m->w, 0);
}

static void rk4(Instance *m, double h) {
    int i, s;
    static const double stage[3] = {0.5, 0.5, 1.0};
    rate(m, m->x, m->k[0]);
    for (s = 0; s < 3; ++s) {
        for (i = 0; i < NX; ++i) m->trial[i] = m->x[i] + stage[s] * h * m->k[s][i];
        rate(m, m->trial, m->k[s + 1]);
    }
    for (i = 0; i < NX; ++i)
        m->x[i] += h / 6.0 * (m->k[0][i] + 2.0 * m->k[1][i] + 2.0 * m->k[2][i] + m->k[3][i]);
}

static void update_outputs(Instance *m) {
    limit_thrust(m);
    memcpy(m->r + VR_STATE, m->x, sizeof m->x);
    m->arg[0] = m->thrust;
    m->res[0] = m->r + VR_LOADS;
    m->res[1] = m->r + VR_LOADS + 3;
    cdb_loads(m->arg, m->res, m->iw, m->w, 0);
}

/* At rest, arrays undeformed, the star tracker at the true attitude. */
static fmi2Status initial_state(Instance *m) {
    int i;
    double norm = 0.0;
    for (i = 0; i < 4; ++i) norm += m->r[VR_INIT + i] * m->r[VR_INIT + i];
    norm = sqrt(norm);
    if (!(norm > 0.0) || !isfinite(norm))
        return fail(m, "initial_q0_BN..initial_q3_BN", "must be finite and not all zero");
    memset(m->x, 0, sizeof m->x);
    for (i = 0; i < 4; ++i) m->x[i] = m->x[Q_ST + i] = m->r[VR_INIT + i] / norm;
    for (i = 0; i < 3; ++i) m->x[4 + i] = m->r[VR_INIT + 4 + i];
    update_outputs(m);
    return fmi2OK;
}

CDB_EXPORT const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
CDB_EXPORT const char *fmi2GetVersion(void) { return fmi2Version; }

CDB_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn,
                                          size_t nCategories, const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    ((Instance *)c)->logging = loggingOn;
    return fmi2OK;
}

CDB_EXPORT fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType,
                                         fmi2String fmuGUID, fmi2String fmuResourceLocation,
                                         const fmi2CallbackFunctions *functions,
                                         fmi2Boolean visible, fmi2Boolean loggingOn) {
    Instance *m;
    (void)fmuResourceLocation;
    (void)visible;
    if (functions == NULL || functions->allocateMemory == NULL || functions->freeMemory == NULL)
        return NULL;
    m = (Instance *)functions->allocateMemory(1, sizeof(Instance));
    if (m == NULL) return NULL;
    m->cb = *functions;
    m->logging = loggingOn;
    snprintf(m->name, sizeof m->name, "%s", instanceName ? instanceName : "${IDENTIFIER}");
    if (fmuType != fmi2CoSimulation) {
        fail(m, "fmi2Instantiate", "this FMU is for co-simulation only");
        functions->freeMemory(m);
        return NULL;
    }
    if (fmuGUID == NULL || strcmp(fmuGUID, GUID) != 0) {
        fail(m, "fmi2Instantiate", "the GUID does not match this FMU's " GUID);
        functions->freeMemory(m);
        return NULL;
    }
    memcpy(m->r, start_values, sizeof m->r);
    m->phase = INSTANTIATED;
    m->time = 0.0;
    if (initial_state(m) != fmi2OK) {
        functions->freeMemory(m);
        return NULL;
    }
    return m;
}

CDB_EXPORT void fmi2FreeInstance(fmi2Component c) {
    Instance *m = (Instance *)c;
    if (m != NULL) m->cb.freeMemory(m);
}

CDB_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                                          fmi2Real tolerance, fmi2Real startTime,
                                          fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Instance *m = (Instance *)c;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (m->phase != INSTANTIATED) return fail(m, "fmi2SetupExperiment", "only after instantiation");
    m->time = startTime;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Instance *m = (Instance *)c;
    if (m->phase != INSTANTIATED) return fail(m, "fmi2EnterInitializationMode", "wrong state");
    m->phase = INITIALIZATION;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *m = (Instance *)c;
    int i;
    if (m->phase != INITIALIZATION) return fail(m, "fmi2ExitInitializationMode", "wrong state");
    for (i = 0; i < N_POSITIVE; ++i)
        if (!(m->r[positive[i]] > 0.0)) {
            report(m, fmi2Error, "parameter %s must be positive, got %g", names[positive[i]],
                   m->r[positive[i]]);
            return fmi2Error;
        }
    if (initial_state(m) != fmi2OK) return fmi2Error;
    m->phase = STEPPING;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
    ((Instance *)c)->phase = TERMINATED;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2Reset(fmi2Component c) {
    Instance *m = (Instance *)c;
    memcpy(m->r, start_values, sizeof m->r);
    m->phase = INSTANTIATED;
    m->time = 0.0;
    return initial_state(m);
}

CDB_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                  fmi2Real value[]) {
    Instance *m = (Instance *)c;
    size_t i;
    if (m->phase == INSTANTIATED || m->phase == INITIALIZATION) {
        if (initial_state(m) != fmi2OK) return fmi2Error;
    } else {
        update_outputs(m);
    }
    for (i = 0; i < nvr; ++i) {
        if (vr[i] >= NR) return fail(m, "fmi2GetReal", "unknown value reference");
        value[i] = m->r[vr[i]];
    }
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                  const fmi2Real value[]) {
    Instance *m = (Instance *)c;
    size_t i;
    for (i = 0; i < nvr; ++i) {
        if (vr[i] >= NR) return fail(m, "fmi2SetReal", "unknown value reference");
        if (vr[i] >= VR_STATE) return fail(m, names[vr[i]], "an output cannot be set");
        if (vr[i] < VR_THRUST && m->phase != INSTANTIATED && m->phase != INITIALIZATION)
            return fail(m, names[vr[i]], "a parameter is fixed after initialisation");
        if (!isfinite(value[i])) {
            report(m, fmi2Error, "fmi2SetReal: %s must be finite", names[vr[i]]);
            return fmi2Error;
        }
        m->r[vr[i]] = value[i];
    }
    return fmi2OK;
}

static fmi2Status no_variables(Instance *m, size_t nvr, const char *where) {
    return nvr == 0 ? fmi2OK : fail(m, where, "this FMU has Real variables only");
}

CDB_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2Integer value[]) {
    (void)vr;
    (void)value;
    return no_variables((Instance *)c, nvr, "fmi2GetInteger");
}

CDB_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     fmi2Boolean value[]) {
    (void)vr;
    (void)value;
    return no_variables((Instance *)c, nvr, "fmi2GetBoolean");
}

CDB_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                    fmi2String value[]) {
    (void)vr;
    (void)value;
    return no_variables((Instance *)c, nvr, "fmi2GetString");
}

CDB_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2Integer value[]) {
    (void)vr;
    (void)value;
    return no_variables((Instance *)c, nvr, "fmi2SetInteger");
}

CDB_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                     const fmi2Boolean value[]) {
    (void)vr;
    (void)value;
    return no_variables((Instance *)c, nvr, "fmi2SetBoolean");
}

CDB_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                    const fmi2String value[]) {
    (void)vr;
    (void)value;
    return no_variables((Instance *)c, nvr, "fmi2SetString");
}

/* The whole instance is the state: a copy restores it (the callbacks included). */
CDB_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    Instance *m = (Instance *)c;
    Instance *copy = (Instance *)*FMUstate;
    if (copy == NULL) copy = (Instance *)m->cb.allocateMemory(1, sizeof(Instance));
    if (copy == NULL) return fail(m, "fmi2GetFMUstate", "out of memory");
    memcpy(copy, m, sizeof(Instance));
    *FMUstate = copy;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    Instance *m = (Instance *)c;
    if (FMUstate == NULL) return fail(m, "fmi2SetFMUstate", "no state given");
    memcpy(m, FMUstate, sizeof(Instance));
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    Instance *m = (Instance *)c;
    if (FMUstate != NULL && *FMUstate != NULL) {
        m->cb.freeMemory(*FMUstate);
        *FMUstate = NULL;
    }
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate,
                                                 size_t *size) {
    (void)FMUstate;
    (void)size;
    return fail((Instance *)c, "fmi2SerializedFMUstateSize", "not supported");
}

CDB_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate,
                                            fmi2Byte serializedState[], size_t size) {
    (void)FMUstate;
    (void)serializedState;
    (void)size;
    return fail((Instance *)c, "fmi2SerializeFMUstate", "not supported");
}

CDB_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[],
                                              size_t size, fmi2FMUstate *FMUstate) {
    (void)serializedState;
    (void)size;
    (void)FMUstate;
    return fail((Instance *)c, "fmi2DeSerializeFMUstate", "not supported");
}

CDB_EXPORT fmi2Status fmi2GetDirectionalDerivative(
    fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
    const fmi2ValueReference vKnown_ref[], size_t nKnown, const fmi2Real dvKnown[],
    fmi2Real dvUnknown[]) {
    (void)vUnknown_ref;
    (void)nUnknown;
    (void)vKnown_ref;
    (void)nKnown;
    (void)dvKnown;
    (void)dvUnknown;
    return fail((Instance *)c, "fmi2GetDirectionalDerivative", "not provided");
}

CDB_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                                  size_t nvr, const fmi2Integer order[],
                                                  const fmi2Real value[]) {
    (void)vr;
    (void)order;
    (void)value;
    return nvr == 0 ? fmi2OK
                    : fail((Instance *)c, "fmi2SetRealInputDerivatives", "inputs are held");
}

CDB_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                                   size_t nvr, const fmi2Integer order[],
                                                   fmi2Real value[]) {
    (void)vr;
    (void)order;
    (void)value;
    return nvr == 0 ? fmi2OK
                    : fail((Instance *)c, "fmi2GetRealOutputDerivatives", "not provided");
}

CDB_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                                 fmi2Real communicationStepSize,
                                 fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Instance *m = (Instance *)c;
    double substeps, h;
    long n, i;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (m->phase != STEPPING) return fail(m, "fmi2DoStep", "not initialised, or failed");
    if (!(communicationStepSize > 0.0) || !isfinite(communicationStepSize))
        return fail(m, "fmi2DoStep", "the communication step must be positive");
    substeps = ceil(communicationStepSize / m->r[VR_MAX_STEP]);
    if (substeps > MAX_SUBSTEPS) return fail(m, "fmi2DoStep", "max_step_s is too small");
    n = (long)substeps;
    h = communicationStepSize / (double)n;
    limit_thrust(m);
    for (i = 0; i < n; ++i) rk4(m, h);
    for (i = 0; i < NX; ++i)
        if (!isfinite(m->x[i])) {
            m->phase = FAILED;
            return fail(m, "fmi2DoStep", "the state is no longer finite");
        }
    m->time = currentCommunicationPoint + communicationStepSize;
    update_outputs(m);
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2CancelStep(fmi2Component c) {
    return fail((Instance *)c, "fmi2CancelStep", "steps are synchronous");
}

CDB_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s;
    (void)value;
    return fail((Instance *)c, "fmi2GetStatus", "steps are synchronous");
}

CDB_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s,
                                        fmi2Real *value) {
    Instance *m = (Instance *)c;
    if (s != fmi2LastSuccessfulTime) return fail(m, "fmi2GetRealStatus", "unknown status kind");
    *value = m->time;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s,
                                           fmi2Integer *value) {
    (void)s;
    (void)value;
    return fail((Instance *)c, "fmi2GetIntegerStatus", "no integer status");
}

CDB_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s,
                                           fmi2Boolean *value) {
    Instance *m = (Instance *)c;
    if (s != fmi2Terminated) return fail(m, "fmi2GetBooleanStatus", "unknown status kind");
    *value = fmi2False;
    return fmi2OK;
}

CDB_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s,
                                          fmi2String *value) {
    (void)s;
    (void)value;
    return fail((Instance *)c, "fmi2GetStringStatus", "no string status");
}
"""
