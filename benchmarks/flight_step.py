"""Flight-step benchmark: time per ``cdb_step`` of the exported C on the paper's slew.

Exports ``paper_slew``, records what the Python closed loop's star tracker measured over
the slew, and replays it through the compiled step (``-O2``) in a small C timing harness,
several times; per step the best of the repeats is kept (the machine's other load only
ever adds time). Prints JSON:

- ``step_us``: median, p99, maximum and the count above 5 us over every period of the
  slew, and over its saturated periods alone; the largest solver iteration count;
- ``python_loop_us_per_step``: the Python loop's wall time per period (the whole loop:
  plant integration included, so an upper bound on its control part);
- ``size_bytes``: text, data and bss of each object (``size``), the reference table apart;
- ``stack_bytes``: each function's frame (``-fstack-usage``) and their sum along the
  deepest call chain of the step (an upper bound on the stack it needs).

Not a test: numbers depend on the machine and its load.

Usage: python benchmarks/flight_step.py [--repeats N] [--out FILE]
"""

from __future__ import annotations

import argparse
import csv
import json
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

import casadi_debris as cd
from casadi_debris.dynamics import build_model

TIMER = r"""
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "cdb_flight.h"
#define MAX_STEPS 200000
static cdb_inputs inputs[MAX_STEPS];
static double best[MAX_STEPS];
static int iterations[MAX_STEPS];
static unsigned flags[MAX_STEPS];
int main(int argc, char **argv) {
    FILE *file = fopen(argv[1], "r");
    int repeats = atoi(argv[2]), n = 0, i, k, r;
    static char line[65536];
    if (file == NULL || fgets(line, sizeof line, file) == NULL) return 2;
    while (n < MAX_STEPS && fgets(line, sizeof line, file) != NULL) {
        char *c = line, *e;
        inputs[n].time_s = strtod(c, &e); c = e + 1;
        for (i = 0; i < 4; ++i) { inputs[n].q_BN[i] = strtod(c, &e); c = e + 1; }
        for (i = 0; i < CDB_N_CUBESATS; ++i) {
            inputs[n].cubesat_failed[i] = (unsigned char)strtol(c, &e, 10); c = e + 1;
        }
        for (i = 0; i < CDB_N_ENGINES; ++i) {
            inputs[n].engine_stage[i] = (int)strtol(c, &e, 10); c = e + 1;
        }
        ++n;
    }
    for (r = 0; r < repeats; ++r) {
        cdb_state state;
        cdb_outputs out;
        cdb_init(&state);
        for (k = 0; k < n; ++k) {
            struct timespec a, b;
            double us;
            clock_gettime(CLOCK_MONOTONIC, &a);
            cdb_step(&inputs[k], &out, &state);
            clock_gettime(CLOCK_MONOTONIC, &b);
            us = (double)(b.tv_sec - a.tv_sec) * 1e6 + (double)(b.tv_nsec - a.tv_nsec) * 1e-3;
            if (r == 0 || us < best[k]) best[k] = us;
            iterations[k] = out.qp_iterations;
            flags[k] = out.flags;
        }
    }
    for (k = 0; k < n; ++k) printf("%.4f %d %u\n", best[k], iterations[k], flags[k]);
    return 0;
}
"""
# The target per period [us].
TARGET_US = 5.0
# The functions on the step's deepest call chain, outermost first (the fallback of the
# least-fuel solve: the simplex, then the active-set method; those the compiler inlines
# have no frame of their own): their frames' sum bounds the stack the step needs.
CALL_CHAIN = (
    "cdb_step",
    "cdb_allocate",
    "exact_thrust",
    "least_fuel",
    "largest_scale",
    "active_set",
    "equality_step",
    "polish",
)


def _record(duration_s: float) -> tuple[np.ndarray, np.ndarray, float]:
    run = cd.simulate("paper_slew", duration_s=duration_s)
    layout = build_model(run.problem).layout
    result = run.result
    steps = len(result.demand_Nm)
    return result.time_s[:steps], result.state[:steps, layout.q_st], result.wall_time_s / steps


def _inputs_csv(path: Path, times: np.ndarray, measured: np.ndarray, sizes: dict) -> None:
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["time_s", "q0", "q1", "q2", "q3"])
        for t, q in zip(times, measured, strict=True):
            writer.writerow(
                [repr(float(t)), *(repr(float(v)) for v in q)]
                + [0] * sizes["cubesats"]
                + [1] * sizes["engines"]
            )


def _stats(values: np.ndarray) -> dict[str, float]:
    if len(values) == 0:
        return {}
    return {
        "median": float(np.median(values)),
        "p99": float(np.percentile(values, 99)),
        "max": float(values.max()),
        "over_5_us": int((values > TARGET_US).sum()),
    }


def _sizes(folder: Path, compiler: str) -> tuple[dict[str, Any], dict[str, Any]]:
    sizes: dict[str, Any] = {}
    frames: dict[str, int] = {}
    for name in ("cdb_step.c", "cdb_alloc.c", "cdb_law.c", "cdb_data.c"):
        obj = folder / name.replace(".c", ".o")
        subprocess.run(
            [compiler, "-std=c99", "-O2", "-fstack-usage", "-c", name, "-o", obj.name],
            cwd=folder,
            check=True,
        )
        text, data, bss = (
            subprocess.run(
                ["size", obj.name], cwd=folder, capture_output=True, text=True, check=True
            )
            .stdout.splitlines()[1]
            .split()[:3]
        )
        sizes[name] = {"text": int(text), "data": int(data), "bss": int(bss)}
        usage = folder / name.replace(".c", ".su")
        for line in usage.read_text().splitlines():
            location, size, _ = line.split("\t")
            frames[location.rsplit(":", 1)[-1]] = int(size)
    chain = sum(frames.get(name, 0) for name in CALL_CHAIN)
    return sizes, {"frames": frames, "call_chain": list(CALL_CHAIN), "call_chain_sum": chain}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        raise SystemExit("no C compiler on PATH")
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch) / "export"
        exported = cd.export("paper_slew", out=folder)
        sizes = exported.manifest["sizes"]
        times, measured, python_us = _record(1500.0)
        inputs = Path(scratch) / "inputs.csv"
        _inputs_csv(inputs, times, measured, sizes)
        (folder / "timer.c").write_text(TIMER)
        sources = ["timer.c", "cdb_step.c", "cdb_alloc.c", "cdb_law.c", "cdb_data.c"]
        subprocess.run(
            [compiler, "-std=c99", "-O2", "-o", "timer", *sources, "-lm"], cwd=folder, check=True
        )
        done = subprocess.run(
            [str(folder / "timer"), str(inputs), str(args.repeats)],
            capture_output=True,
            text=True,
            check=True,
        )
        table = np.array([line.split() for line in done.stdout.splitlines()], dtype=float)
        step_us, iterations, flags = table[:, 0], table[:, 1], table[:, 2].astype(int)
        saturated = (flags & 1) == 1
        code, stack = _sizes(folder, compiler)
    report = {
        "problem": "paper_slew",
        "steps": len(step_us),
        "repeats": args.repeats,
        "step_us": {
            "all": _stats(step_us),
            "saturated": _stats(step_us[saturated]),
            "saturated_steps": int(saturated.sum()),
        },
        "max_iterations": int(iterations.max()),
        "python_loop_us_per_step": python_us * 1e6,
        "size_bytes": code,
        "stack_bytes": stack,
    }
    text = json.dumps(report, indent=2)
    print(text)
    if args.out is not None:
        args.out.write_text(text + "\n")


if __name__ == "__main__":
    main()
