/* cdb_step.c - one control period: reference, attitude error and controller (the generated
 * control law), engine limits from the propulsion state, allocation. The order and the
 * arithmetic are those of casadi_debris' closed loop. */
#include <math.h>
#include "cdb_flight.h"
#include "cdb_law.h"

unsigned long cdb_state_bytes(void) { return (unsigned long)sizeof(cdb_state); }

int cdb_init(cdb_state *state) {
    int i;
    for (i = 0; i < CDB_N_CONTROLLER; ++i) {
        state->xc[i] = (cdb_real)0;
    }
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        state->limit[i] = (cdb_real)-1;
    }
    for (i = 0; i < CDB_N_ROWS; ++i) {
        state->lambda_exact[i] = (cdb_real)0;
    }
    state->warm_exact = 0;
    state->saturated = 0;
    return 0;
}

/* Row of the reference table for time t: the control instant nearest t, held after the
 * table's end (the reference is constant there) and before its start. */
static long reference_row(cdb_real time_s) {
    double k = floor((double)time_s / CDB_PERIOD_S + 0.5);
    if (!(k > 0.0)) {
        return 0;
    }
    if (k >= (double)(CDB_N_REFERENCE - 1)) {
        return CDB_N_REFERENCE - 1;
    }
    return (long)k;
}

static void zero_outputs(cdb_outputs *out) {
    int i;
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        out->thrust_N[i] = (cdb_real)0;
        out->engine_stage[i] = 0;
    }
    for (i = 0; i < 3; ++i) {
        out->demand_Nm[i] = (cdb_real)0;
        out->torque_Nm[i] = (cdb_real)0;
        out->error_rad[i] = (cdb_real)0;
    }
    for (i = 0; i < 4; ++i) {
        out->reference_BN[i] = (cdb_real)0;
    }
    out->scale = (cdb_real)0;
    out->qp_iterations = 0;
    out->flags = 0u;
}

static int is_finite(cdb_real v) { return v - v == (cdb_real)0; }

int cdb_step(const cdb_inputs *in, cdb_outputs *out, cdb_state *state) {
    const cdb_real *arg[CDB_LAW_SZ_ARG];
    cdb_real *res[CDB_LAW_SZ_RES];
    cdb_real xc_next[CDB_N_CONTROLLER];
    cdb_real limit_N[CDB_N_ENGINES];
    const cdb_real *row;
    cdb_real norm = (cdb_real)0;
    int i, j;
    zero_outputs(out);
    for (i = 0; i < 4; ++i) {
        if (!is_finite(in->q_BN[i])) {
            out->flags = CDB_FLAG_BAD_INPUT;
            return 1;
        }
        norm += in->q_BN[i] * in->q_BN[i];
    }
    if (!is_finite(in->time_s) || !(norm > (cdb_real)0)) {
        out->flags = CDB_FLAG_BAD_INPUT;
        return 1;
    }
    row = &cdb_reference[reference_row(in->time_s) * 7];
    for (i = 0; i < 4; ++i) {
        out->reference_BN[i] = row[i];
    }
    arg[0] = in->q_BN;
    arg[1] = state->xc;
    arg[2] = row;
    arg[3] = row + 4;
    res[0] = out->demand_Nm;
    res[1] = xc_next;
    res[2] = out->error_rad;
    if (cdb_law(arg, res, state->law_iw, state->law_w, 0) != 0) {
        out->flags = CDB_FLAG_BAD_INPUT;
        return 1;
    }
    for (i = 0; i < CDB_N_CONTROLLER; ++i) {
        state->xc[i] = xc_next[i];
    }
    /* Engine limits: the thrust of the active stage; 0 for a failed CubeSat or none left. */
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        int stage = in->engine_stage[i];
        limit_N[i] = (cdb_real)0;
        if (stage >= 1 && stage <= CDB_N_STAGES && !in->cubesat_failed[cdb_engine_cubesat[i]]) {
            limit_N[i] = cdb_stage_thrust_N[i * CDB_N_STAGES + (stage - 1)];
        }
    }
    out->flags = cdb_allocate(out->demand_Nm, limit_N, out->thrust_N, &out->scale,
                              &out->qp_iterations, state);
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        out->engine_stage[i] = limit_N[i] > (cdb_real)0 ? in->engine_stage[i] : 0;
    }
    for (j = 0; j < 3; ++j) {
        cdb_real t = (cdb_real)0;
        for (i = 0; i < CDB_N_ENGINES; ++i) {
            t += cdb_torque_map[j * CDB_N_ENGINES + i] * out->thrust_N[i];
        }
        out->torque_Nm[j] = t;
    }
    return 0;
}
