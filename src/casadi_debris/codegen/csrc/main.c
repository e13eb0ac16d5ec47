/* main.c - replay harness: reads an input CSV (one control period per row), runs the
 * flight step on each and writes an output CSV. Usage: cdb_replay inputs.csv outputs.csv
 * Column layout: see README.md (CubeSats, engines and stages numbered from 1). */
#include <stdio.h>
#include <stdlib.h>
#include "cdb_flight.h"

#define LINE_CHARS 65536
#define MAX_ROWS 100000000L

static char line[LINE_CHARS];

/* Next number of a CSV line; 0 when there is none. */
static int next_number(char **cursor, double *value) {
    char *end;
    if (**cursor == ',') {
        ++*cursor;
    }
    *value = strtod(*cursor, &end);
    if (end == *cursor) {
        return 0;
    }
    *cursor = end;
    return 1;
}

static int parse(char *text, cdb_inputs *in) {
    double v;
    char *cursor = text;
    int i;
    if (!next_number(&cursor, &v)) {
        return 0;
    }
    in->time_s = (cdb_real)v;
    for (i = 0; i < 4; ++i) {
        if (!next_number(&cursor, &v)) {
            return 0;
        }
        in->q_BN[i] = (cdb_real)v;
    }
    for (i = 0; i < CDB_N_CUBESATS; ++i) {
        if (!next_number(&cursor, &v)) {
            return 0;
        }
        in->cubesat_failed[i] = (unsigned char)(v != 0.0);
    }
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        if (!next_number(&cursor, &v)) {
            return 0;
        }
        in->engine_stage[i] = (int)v;
    }
    return 1;
}

static void write_header(FILE *out) {
    int i;
    const char *axes = "xyz";
    fprintf(out, "time_s");
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        fprintf(out, ",thrust_%d_N", i + 1);
    }
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        fprintf(out, ",stage_%d", i + 1);
    }
    for (i = 0; i < 3; ++i) {
        fprintf(out, ",demand_%c_Nm", axes[i]);
    }
    for (i = 0; i < 3; ++i) {
        fprintf(out, ",torque_%c_Nm", axes[i]);
    }
    for (i = 0; i < 3; ++i) {
        fprintf(out, ",error_%c_rad", axes[i]);
    }
    fprintf(out, ",scale,flags,qp_iterations\n");
}

static void write_row(FILE *out, const cdb_inputs *in, const cdb_outputs *o) {
    int i;
    fprintf(out, "%.17g", (double)in->time_s);
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        fprintf(out, ",%.17g", (double)o->thrust_N[i]);
    }
    for (i = 0; i < CDB_N_ENGINES; ++i) {
        fprintf(out, ",%d", o->engine_stage[i]);
    }
    for (i = 0; i < 3; ++i) {
        fprintf(out, ",%.17g", (double)o->demand_Nm[i]);
    }
    for (i = 0; i < 3; ++i) {
        fprintf(out, ",%.17g", (double)o->torque_Nm[i]);
    }
    for (i = 0; i < 3; ++i) {
        fprintf(out, ",%.17g", (double)o->error_rad[i]);
    }
    fprintf(out, ",%.17g,%u,%d\n", (double)o->scale, o->flags, o->qp_iterations);
}

int main(int argc, char **argv) {
    FILE *input, *output;
    cdb_state state;
    cdb_inputs in;
    cdb_outputs out;
    long row;
    if (argc != 3) {
        fprintf(stderr, "usage: %s inputs.csv outputs.csv\n", argv[0]);
        return 2;
    }
    input = fopen(argv[1], "r");
    if (input == NULL) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 2;
    }
    output = fopen(argv[2], "w");
    if (output == NULL) {
        fprintf(stderr, "cannot write %s\n", argv[2]);
        fclose(input);
        return 2;
    }
    cdb_init(&state);
    write_header(output);
    if (fgets(line, LINE_CHARS, input) == NULL) { /* the header line */
        fclose(input);
        fclose(output);
        return 0;
    }
    for (row = 0; row < MAX_ROWS && fgets(line, LINE_CHARS, input) != NULL; ++row) {
        if (!parse(line, &in)) {
            fprintf(stderr, "%s: row %ld: expected %d numbers\n", argv[1], row + 2,
                    5 + CDB_N_CUBESATS + CDB_N_ENGINES);
            fclose(input);
            fclose(output);
            return 2;
        }
        cdb_step(&in, &out, &state);
        write_row(output, &in, &out);
    }
    fclose(input);
    return fclose(output) == 0 ? 0 : 1;
}
