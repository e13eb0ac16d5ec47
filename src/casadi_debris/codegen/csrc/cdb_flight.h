/* cdb_flight.h - the flight step of a casadi_debris problem: reference, attitude error,
 * discrete robust controller and least-fuel thrust allocation, one call per control period.
 *
 * Portable C99: no dynamic memory, no recursion, no mutable data outside cdb_state,
 * every loop bounded. Sizes and constants of this export are in cdb_config.h.
 * Units SI (N, N m, rad, s); quaternions scalar first, attitude of the body frame B
 * relative to the inertial frame N (q_BN). Arrays are indexed from 0 in C; the CSV
 * files of main.c and the README number CubeSats, engines and stages from 1.
 */
#ifndef CDB_FLIGHT_H
#define CDB_FLIGHT_H

#include "cdb_config.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Status flags of cdb_outputs.flags. */
#define CDB_FLAG_SATURATED 1u          /* the demand was beyond reach: scaled by `scale` < 1 */
#define CDB_FLAG_INFEASIBLE 2u         /* no allocation found: thrust set to zero */
#define CDB_FLAG_ESTIMATOR_REJECTED 4u /* a measurement was rejected (no estimator in this export) */
#define CDB_FLAG_NO_ENGINE 8u          /* every engine failed or spent: thrust zero */
#define CDB_FLAG_BAD_INPUT 16u         /* non-finite or zero quaternion, or non-finite time */

typedef struct {
    cdb_real time_s;                          /* time since the start of the reference [s] */
    cdb_real q_BN[4];                         /* measured attitude (star tracker), scalar first */
    unsigned char cubesat_failed[CDB_N_CUBESATS]; /* 1: this CubeSat does not fire */
    int engine_stage[CDB_N_ENGINES];          /* active stage of each engine, 1-based; 0: none left */
} cdb_inputs;

typedef struct {
    cdb_real thrust_N[CDB_N_ENGINES];   /* thrust of every engine [N] */
    int engine_stage[CDB_N_ENGINES];    /* stage the thrust is drawn from (1-based), 0 if none */
    cdb_real demand_Nm[3];              /* controller's torque demand, body axes [N m] */
    cdb_real torque_Nm[3];              /* commanded torque the thrusts make, body axes [N m] */
    cdb_real error_rad[3];              /* attitude error (attitude minus reference) [rad] */
    cdb_real reference_BN[4];           /* reference attitude followed at this time */
    cdb_real scale;                     /* saturation factor in [0, 1] (1: demand met) */
    int qp_iterations;                  /* Newton iterations of the allocation QPs */
    unsigned int flags;                 /* CDB_FLAG_* */
} cdb_outputs;

typedef struct {
    cdb_real xc[CDB_N_CONTROLLER];      /* controller state */
    cdb_real limit[CDB_N_ENGINES];      /* scaled thrust limits of the last step */
    cdb_real lambda_exact[CDB_N_ROWS];  /* warm start of the least-fuel QP (dual) */
    int warm_exact;
    int saturated;                      /* the last period's demand was beyond reach */
    cdb_real law_w[CDB_LAW_SZ_W + 1];   /* workspace of the generated control law */
    casadi_int law_iw[CDB_LAW_SZ_IW + 1];
} cdb_state;

/* sizeof(cdb_state), for callers that hold the state in their own memory (bindings). */
unsigned long cdb_state_bytes(void);

/* Reset the state: controller at rest, no warm start. Returns 0. */
int cdb_init(cdb_state *state);

/* One control period. Returns 0, or 1 when the inputs were refused (outputs zero
 * thrust and CDB_FLAG_BAD_INPUT). */
int cdb_step(const cdb_inputs *in, cdb_outputs *out, cdb_state *state);

/* Allocation alone: thrust for a torque demand [N m] with the engine limits `limit_N`
 * (N per engine, 0 removes it), as the step does it. Returns the flags. */
unsigned int cdb_allocate(const cdb_real demand_Nm[3], const cdb_real limit_N[CDB_N_ENGINES],
                          cdb_real thrust_N[CDB_N_ENGINES], cdb_real *scale, int *iterations,
                          cdb_state *state);

#ifdef __cplusplus
}
#endif

#endif /* CDB_FLIGHT_H */
