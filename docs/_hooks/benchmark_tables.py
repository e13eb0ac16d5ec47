"""MkDocs hook: the benchmark page's tables, rendered from the recorded results.

``python benchmarks/<name>.py --record`` writes ``docs/benchmarks/<name>.json``
(the figures, the machine, the date, the commit, how busy the machine was). A
page asks for a table with a line of its own::

    <!-- benchmark allocation per_call -->

and the hook replaces it with Markdown built from ``docs/benchmarks/allocation.json``.
``<!-- benchmark <name> recording -->`` gives when, where and how ``<name>`` was
recorded, with a link to its JSON; ``<!-- benchmark recordings -->`` a table of
all of them, in the order the page shows them; ``<!-- benchmark references -->`` one
table of the checks against outside references (slew_global, musyn_distillation,
mu_bounds). A missing file, a missing figure or
an unknown table is a warning, so an error under ``mkdocs build --strict``.
Nothing is written to ``docs/``.
"""

from __future__ import annotations

import json
import logging
import posixpath
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.structure.files import Files
from mkdocs.structure.pages import Page

# mkdocs loads a hook by its path: its sibling modules are importable from its folder.
sys.path.insert(0, str(Path(__file__).resolve().parent))
from benchmark_format import (
    Data,
    MissingFigureError,
    _get,
    _label,
    _met,
    _runs,
    _target,
    fraction,
    num,
    table,
    when,
)
from benchmark_references import (
    mu_bounds,
    musyn_distillation,
    references,
    slew_global,
)

RESULTS = "benchmarks"  # under docs_dir
MARKER = re.compile(r"^<!-- benchmark (\w+)(?: (\w+))? -->$", re.MULTILINE)
REFERENCED = ("slew_global", "musyn_distillation", "mu_bounds")
UNDER_LOAD_SHARE = 0.1  # other work's share of the CPU time above which a run was "under load"
log = logging.getLogger("mkdocs.hooks.benchmark_tables")


# ---------------------------------------------------------------- allocation

ALLOCATION_METHODS = {
    "pseudo_inverse": "pseudo-inverse + bias + clip",
    "daqp": "DAQP (default)",
    "osqp": "OSQP (native, polished)",
}


def allocation_per_call(data: Data) -> str:
    per_call, saturation = _get(data, "per_call"), data.get("saturation", {})
    rows = []
    for method, entry in per_call.items():
        feasible = _get(entry, "feasible")
        saturating = entry.get("saturating")
        quality = saturation.get(method)
        rows.append(
            [
                _label(method, ALLOCATION_METHODS),
                str(entry.get("calls", _get(data, "run", "settings", "calls"))),
                f"{num(feasible['median_us'])} / {num(feasible['p99_us'])}",
                num(feasible.get("backend_median_us")),
                "–"
                if saturating is None
                else f"{num(saturating['median_us'])} / {num(saturating['p99_us'])}",
                num(_get(entry, "ratio_to_pseudo_inverse")),
                "–"
                if quality is None
                else f"{fraction(quality['fraction_of_lp_max_median'])} "
                f"(min {fraction(quality['fraction_of_lp_max_min'])})",
                "–" if quality is None else num(quality["angle_error_max_rad"], 2),
            ]
        )
    return table(
        [
            "method",
            "demands",
            "feasible: median / p99 [µs]",
            "back-end only, feasible median [µs]",
            "saturating: median / p99 [µs]",
            "feasible median / pseudo-inverse's",
            "fraction of the LP's largest torque, saturating: median (min)",
            "largest angle error, saturating [rad]",
        ],
        rows,
    )


def allocation_other(data: Data) -> str:
    batch, series, tiny = _get(data, "batch"), _get(data, "series"), _get(data, "tiny")
    rows = [
        [
            f"`allocate_batch`, {batch['demands']:,} mixed demands",
            f"{num(batch['solves_per_s'])} solves per second",
        ],
        [
            f"`allocate_series`, {series['steps']:,}-step history "
            f"({series['saturated_fraction']:.0%} of the steps saturated), median of "
            f"{series['repeats']} runs",
            f"{num(series['series_per_step_median_us'])} µs per step "
            f"({series['point_solves']:,} point solves)",
        ],
        ["its authority polytope, built once", f"{num(series['polytope_median_ms'])} ms"],
        [
            "a loop of `allocate` over the same history",
            f"{num(series['allocate_loop_per_step_median_us'])} µs per step, median: "
            f"{num(series['speed_up_median'])} times the series' time",
        ],
        [
            f"`allocate` on {tiny['demands']:,} tiny demands (1e-300 to 1e-4 N m, and subnormal)",
            f"{num(tiny['median_us'])} µs median; relative torque error at most "
            f"{num(tiny['max_relative_error_normal'], 2)} (normal), "
            f"{num(tiny['max_error_subnormal_in_floors'], 2)} floors (subnormal); "
            f"{tiny['highs_fallbacks']} HiGHS fallbacks",
        ],
    ]
    scaling = data.get("engines_scaling")
    if scaling:  # recordings before it was measured have none
        rows.append(
            [
                f"`allocate` with {scaling['48']['engines']} engines against "
                f"{scaling['24']['engines']} (feasible demands, same run)",
                f"{num(scaling['48']['median_us'])} µs against "
                f"{num(scaling['24']['median_us'])} µs median: "
                f"{num(scaling['ratio_48_to_24'])} times",
            ]
        )
    return table(["figure", "measured"], rows, "ll")


# ---------------------------------------------------------------- synthesis

SYNTHESIS_STAGES = {
    "samples_s": "sampling the uncertain plants",
    "weight_s": "fitting the uncertainty weight",
    "dk_s": "D-K iteration",
    "reduce_s": "reducing the controller",
}


def synthesis(data: Data) -> str:
    targets = data.get("targets", {})
    rows = []
    if "synthesis_s" in data:
        iterations = data.get("dk_iterations", [])
        rows.append(
            [
                "whole synthesis",
                f"{num(data['synthesis_s'])} s",
                _target(targets.get("synthesis_s"), "s"),
            ]
        )
        for stage, seconds in _get(data, "stage_times_s").items():
            label = _label(stage, SYNTHESIS_STAGES)
            if stage == "dk_s" and iterations:
                label += f" ({len(iterations)} iterations)"
            rows.append([f"of which {label}", f"{num(seconds)} s", ""])
        rows.append(
            [
                "μ peak (full controller / reduced)",
                f"{num(data['mu_peak'], 4)} / {num(data['mu_peak_reduced'], 4)}",
                "",
            ]
        )
    samples = _get(data, "margin_sweep_samples")
    for workers, key in ((1, "1_worker"), (2, "2_workers")):
        rows.append(
            [
                f"margin sweep, {samples:,} plants, {workers} worker{'s' * (workers > 1)} "
                f"(1-min load average before: {num(data[f'load_average_1min_before_{key}'], 2)})",
                f"{num(data[f'margin_sweep_s_{key}'])} s",
                _target(targets.get(f"margin_sweep_s_{key}"), "s"),
            ]
        )
    rows.append(
        ["margin sweep, 1 worker's time / 2 workers'", num(data["margin_sweep_speedup"]), ""]
    )
    return table(["figure", "measured", "target"], rows)


# ---------------------------------------------------------------- slews

SLEW_METHODS = {
    "bang_bang_paper_1228s": "bang-bang, the paper's 1228 s",
    "bang_bang_full_torque": "bang-bang, full torque",
    "time_optimal_rigid": "time-optimal, rigid",
    "time_optimal_rigid_thrusters": "time-optimal, rigid, thruster level",
    "time_optimal_thrusters": "time-optimal, rigid, thruster level",
    "time_optimal_flexible": "time-optimal, flexible",
    "time_optimal_flexible_thrusters": "time-optimal, flexible, thruster level",
    "time_optimal_flexible_zv_shaper": "time-optimal, flexible, ZV shaper",
    "fuel_optimal_1228s": "fuel-optimal, 1228 s",
    "fuel_optimal_1228s_thrusters": "fuel-optimal, 1228 s, thruster level",
    "fuel_optimal_thrusters": "fuel-optimal, thruster level",
    "fuel_optimal_flexible": "fuel-optimal, flexible",
}
SLEWS = {
    "z_180deg": "180° about z",
    "x_90deg": "90° about x",
    "xyz_2rad": "2 rad about [1, 1, 1]",
    "y_45deg": "45° about y",
}


def slew(data: Data) -> str:
    targets = _get(data, "targets")
    rows = [
        [
            _label(name, SLEW_METHODS),
            num(entry["duration_s"], 4),
            num(entry["duration_over_limit"]),
            num(entry["fuel_kg"] * 1e6),
            num(entry["residual_vibration_rad"], 2),
            num(entry["solve_time_s"]),
            num(entry["wall_time_median_s"]),
            str(entry["solver_status"]),
        ]
        for name, entry in _get(data, "methods").items()
    ]
    return table(
        [
            "method",
            "duration [s]",
            "duration / rigid limit",
            "fuel [mg]",
            "residual vibration [rad]",
            "solve time, median [s]",
            "whole call, median [s]",
            "solver status",
        ],
        rows,
        "lrrrrrrl",
    ) + (
        f"\nRigid eigenaxis limit {num(_get(data, 'limit_duration_s'), 4)} s; "
        f"{_runs(_get(data, 'run', 'settings', 'repeat'))} of each method. Every time-optimal "
        f"slew solved within {targets['time_optimal_solve_time_s_max']:g} s: "
        f"{_met(targets['time_optimal_met'])}; the flexible one within "
        f"{targets['flexible_duration_over_limit_max']:g} times the limit: "
        f"{_met(targets['flexible_met'])}.\n"
    )


def slew_battery(data: Data) -> str:
    methods = _get(data, "methods")
    slews = list(next(iter(methods.values()))["slews"]) if methods else []
    target = _get(data, "target_solve_time_s")
    rows = []
    for name, entry in methods.items():
        cells = [
            f"{num(entry['slews'][s]['solve_time_s'])} ({num(entry['slews'][s]['duration_s'], 4)})"
            for s in slews
        ]
        rows.append(
            [
                _label(name, SLEW_METHODS),
                *cells,
                f"{num(entry['solve_time_min_s'])}–{num(entry['solve_time_max_s'])}",
                f"{entry['within_target']} of {len(slews)}",
            ]
        )
    return (
        table(
            [
                "method",
                *(_label(s, SLEWS) for s in slews),
                "range [s]",
                f"within {target:g} s",
            ],
            rows,
        )
        + "\nEach cell: solve time [s] (the slew's duration [s]).\n"
    )


# ---------------------------------------------------------------- simulation


def simulation(data: Data) -> str:
    targets = data.get("targets", {})
    slower = _get(data, "scipy_over_casadi")
    rows = [
        [
            "one control period in the roll-out",
            f"{num(data['step_us'])} µs",
            f"{num(data.get('step_us_compiled'))} µs "
            f"({num(data.get('compile_s'))} s to compile, once per process)",
            "",
        ],
        [
            "whole paper slew, per step (plant, flex, sensor, controller, allocator, engines)",
            f"{num(data['closed_loop_step_us'])} µs",
            f"{num(data['closed_loop_step_us_compiled'])} µs",
            _target(targets.get("closed_loop_step_us"), "µs"),
        ],
        [
            f"real-time factor of the paper slew ({data['steps_paper_slew']:,} steps)",
            num(data["real_time_factor_paper_slew"]),
            num(data["real_time_factor_paper_slew_compiled"]),
            "",
        ],
        [
            "same loop in plain Python with `scipy.integrate.solve_ivp`, per step",
            f"{num(data['scipy_step_us'])} µs ({num(slower)}× the virtual machine's)",
            "",
            "",
        ],
    ]
    cases, walls = _get(data, "montecarlo_cases"), _get(data, "montecarlo_wall_s")
    for label, seconds in walls.items():
        match = re.fullmatch(r"virtual_machine_(\d+)_workers", label)
        if match is None:  # a compiled run: in the row of the virtual machine's
            continue
        workers = int(match.group(1))
        target = targets.get("montecarlo_256_wall_s_2_cores")
        rows.append(
            [
                f"{cases}-corner slew Monte Carlo, {workers} worker{'s' * (workers > 1)}",
                f"{num(seconds)} s",
                f"{num(walls.get(f'compiled_{workers}_workers'))} s",
                _target(target if (cases, workers) == (256, 2) else None, "s"),
            ]
        )
    return table(["figure", "virtual machine", "compiled (JIT)", "target"], rows)


def campaign(data: Data) -> str:
    steps, corners, failures = (_get(data, key) for key in ("step_cpu_us", "corners", "failures"))
    targets = data.get("targets", {})
    step_labels = {
        "batched": "batched (per case; the compiled function mapped over a batch)",
        "compiled_alone": "compiled, one case (`simulate(settings=LoopSettings(jit=True))`)",
        "compiled_constants": "compiled with the authority as constants, through CasADi",
        "virtual_machine": "CasADi's virtual machine",
    }
    rows = [
        [f"one control period, {text}", "", f"{num(steps.get(key))} µs", ""]
        for key, text in step_labels.items()
    ]
    cases, workers = corners["cases"], corners["workers"]
    where = f"{cases} slew corners, {workers} workers"
    target = targets.get("corners_256_wall_s_2_cores") if (cases, workers) == (256, 2) else None
    for key, text in (("batched", "batched"), ("one_by_one", "one by one, compiled")):
        rows.append(
            [
                f"{where}, {text}",
                f"{num(corners[f'{key}_wall_s'])} s",
                f"{num(corners[f'{key}_cpu_s'])} s",
                _target(target if key == "batched" else None, "s"),
            ]
        )
    rows.append(
        [
            f"{where}, one by one on the virtual machine (scaled from a few)",
            f"{num(corners['virtual_machine_wall_s_scaled'])} s",
            f"{num(corners['virtual_machine_cpu_s_scaled'])} s",
            "",
        ]
    )
    if "baseline" in data:
        base = data["baseline"]
        rows.append(
            [
                f"{where}, the code before (scaled from {base['cases']} cases)",
                f"{num(base['corners_wall_s_scaled'])} s",
                f"{num(base['corners_cpu_s_scaled'])} s",
                "",
            ]
        )
    runs = f"{failures['nominal_runs']} nominal and {failures['corner_runs']} corner runs"
    target = targets.get("failures_300_wall_s") if failures["cases"] == 300 else None
    rows.append(
        [
            f"failure campaign, {failures['cases']} cases ({runs}), batched",
            f"{num(failures['batched_wall_s'])} s",
            f"{num(failures['batched_cpu_s'])} s",
            _target(target, "s"),
        ]
    )
    subset = failures["subset"]
    for key, text in (("batched", "batched"), ("virtual_machine", "one by one, virtual machine")):
        rows.append(
            [
                f"{failures['subset_cases']} of its cases, nominal runs, {text}",
                f"{num(subset[f'{key}_wall_s'])} s",
                f"{num(subset[f'{key}_cpu_s'])} s",
                "",
            ]
        )
    return table(["figure", "wall time", "CPU time", "target"], rows)


# ---------------------------------------------------------------- recordings

LIBRARY_NAMES = {
    "numpy": "NumPy",
    "scipy": "SciPy",
    "casadi": "CasADi",
    "control": "python-control",
}


def _machine(data: Data) -> str:
    machine = _get(data, "machine")
    model = f" ({machine['cpu_model']})" if machine.get("cpu_model") else ""
    return f"{machine['cpus']} CPUs{model}"


def _software(data: Data) -> str:
    machine = _get(data, "machine")
    known = ("cpus", "cpus_usable", "cpu_model", "platform", "python")
    versions = [
        f"{_label(key, LIBRARY_NAMES)} {value}"
        for key, value in machine.items()
        if key not in known and value is not None
    ]
    return ", ".join([f"{machine['platform']}, Python {machine['python']}", *versions])


def _load(run: Data) -> str:
    share = run.get("other_work_cpu_share")
    before = run.get("load_average_1min_before")
    average = "" if before is None else f"; 1-minute load average {num(before, 2)} before it"
    if share is None:
        return f"How busy the machine was is not known{average}."
    if share >= UNDER_LOAD_SHARE:
        return (
            f"**Recorded under load:** other work used {share:.0%} of the machine's CPU time "
            f"during the run{average}."
        )
    return f"The machine was otherwise idle (other work: {share:.0%} of its CPU time{average})."


def _commit(run: Data) -> str:
    commit = run.get("git_commit")
    if not commit:
        return "outside a git checkout"
    dirty = " with uncommitted changes" if run.get("git_uncommitted_changes") else ""
    return f"at commit `{commit[:10]}`{dirty}"


def _shown(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    return str(value)


def _settings(run: Data) -> str:
    return ", ".join(f"{key.replace('_', ' ')}: {_shown(v)}" for key, v in run["settings"].items())


def recording(data: Data, link: str) -> str:
    run = _get(data, "run")
    note = f" {run['note'].rstrip('.')}." if run.get("note") else ""
    body = (
        f"`{run['command']}` on {when(run)} "
        f"{_commit(run)}: a {run['mode']} run ({_settings(run)}) that took "
        f"{num(run['elapsed_s'], 2)} s. {_load(run)}{note} "
        f"Machine: {_machine(data)}; {_software(data)}. All figures: [{link.rsplit('/', 1)[-1]}]"
        f"({link})."
    )
    title = f"Recorded {run['date'][:10]} on {_machine(data)}"
    if (run.get("other_work_cpu_share") or 0.0) >= UNDER_LOAD_SHARE:
        title += ", under load"
    return f'!!! note "{title}"\n    {body}\n'


def recordings(found: dict[str, Data], links: dict[str, str]) -> str:
    rows = []
    for name, data in found.items():
        run = _get(data, "run")
        share = run.get("other_work_cpu_share")
        rows.append(
            [
                f"[`{name}`]({links[name]})",
                when(run),
                run["mode"],
                f"{num(run['elapsed_s'], 2)} s",
                _machine(data),
                "–" if share is None else f"{share:.0%}",
                _commit(run).removeprefix("at commit "),
            ]
        )
    return table(
        [
            "benchmark",
            "recorded",
            "run",
            "took",
            "machine",
            "other work's share of the CPU time",
            "commit",
        ],
        rows,
        "llllrrl",
    )


TABLES: dict[tuple[str, str], Callable[[Data], str]] = {
    ("allocation", "per_call"): allocation_per_call,
    ("allocation", "other"): allocation_other,
    ("synthesis", "times"): synthesis,
    ("slew", "methods"): slew,
    ("slew_battery", "methods"): slew_battery,
    ("slew_global", "slews"): slew_global,
    ("simulation", "times"): simulation,
    ("campaign", "times"): campaign,
    ("mu_bounds", "controllers"): mu_bounds,
    ("musyn_distillation", "iterations"): musyn_distillation,
}


def _results(config: MkDocsConfig) -> Path:
    return Path(config["docs_dir"]) / RESULTS


def _link(page: Page, name: str) -> str:
    """Relative Markdown link from ``page`` to ``benchmarks/<name>.json``."""
    folder = posixpath.dirname(page.file.src_uri)
    return posixpath.relpath(f"{RESULTS}/{name}.json", folder or ".")


def _load_json(config: MkDocsConfig, name: str) -> Data | None:
    path = _results(config) / f"{name}.json"
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None


def on_page_markdown(markdown: str, page: Page, config: MkDocsConfig, files: Files) -> str:
    """Replace each ``<!-- benchmark ... -->`` line with its table."""
    if "<!-- benchmark " not in markdown:
        return markdown

    in_page = list(dict.fromkeys(m.group(1) for m in MARKER.finditer(markdown)))

    def render(match: re.Match[str]) -> str:
        name, which = match.group(1), match.group(2)
        where = f"{page.file.src_uri}: <!-- benchmark {name} {which or ''} -->"
        if which is None and name == "recordings":
            names = sorted(
                (path.stem for path in _results(config).glob("*.json")),
                key=lambda n: (n not in in_page, in_page.index(n) if n in in_page else 0, n),
            )
            found = {n: data for n in names if (data := _load_json(config, n)) is not None}
            return recordings(found, {n: _link(page, n) for n in found})
        if which is None and name == "references":
            found = {n: d for n in REFERENCED if (d := _load_json(config, n)) is not None}
            return references(found)
        data = _load_json(config, name)
        if data is None:
            log.warning(f"{where}: no docs/{RESULTS}/{name}.json (benchmarks/{name}.py --record)")
            return f"*No recording: run `python benchmarks/{name}.py --record`.*\n"
        try:
            if which == "recording":
                return recording(data, _link(page, name))
            if (name, which) not in TABLES:
                log.warning(f"{where}: unknown table; known: recording, {sorted(TABLES)}")
                return ""
            return TABLES[name, which](data)
        except (MissingFigureError, KeyError, TypeError) as error:
            log.warning(f"{where}: docs/{RESULTS}/{name}.json lacks a figure: {error}")
            return f"*The recording of `{name}` lacks figures this table needs.*\n"

    return MARKER.sub(render, markdown)
