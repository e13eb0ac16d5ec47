"""``K…`` entries of the command options, command by command.

Every command: an unknown option, a flag given a value, an option missing its
value, the problem-file argument; then each command's own options with values
out of range or of the wrong type. Where the commands write and the other
files they read are in :mod:`.output_folders` and :mod:`.controllers_tables`.
"""

from __future__ import annotations

from .controllers_tables import (
    controller_files,
    controller_options,
    open_loop_options,
    stage_state_options,
)
from .entry import FileSpec
from .invocations import (
    BASE,
    DURATION,
    HEAVY,
    INT_COUNT,
    SEED_VALUES,
    SHORT_TOML,
    Invocations,
    replace_option,
)
from .output_folders import out_folder_options

# --- every command: option syntax, the problem argument, the group -----------

_FLAGS = ("--json", "--no-plots", "--no-jit", "--quick")


def _option_syntax_entries(inv: Invocations) -> None:
    """Every command: an unknown option, a flag given a value, an option missing its value."""
    for command, base in BASE.items():
        inv.add(
            command,
            [*base, "--bogus"],
            "unknown option --bogus",
            ("--bogus",),
            fast=True,
            category="unknown-option",
        )
        inv.add(
            command,
            [*base, "--json=1"],
            "--json=1 (a flag with a value)",
            ("--json",),
            fast=command not in HEAVY or command in ("simulate", "margins"),
            category="flag-value",
        )
        with_values = [a for a in base if a.startswith("--") and a not in _FLAGS]
        if with_values:
            opt = with_values[0]
            inv.add(
                command,
                replace_option(base, opt, []),
                f"{opt} without its value",
                (opt,),
                fast=True,
                category="missing-value",
            )


def _problem_argument_entries(inv: Invocations) -> None:
    """The problem file missing, a directory, /dev/null, a FIFO; two problem files."""
    for command in ("model", "budget", "allocate", "slew", "simulate", "margins"):
        base = [a for a in BASE[command] if a != SHORT_TOML]
        fast = command in ("model", "budget", "allocate")
        for arg, desc, files in (
            ("nope.toml", "a missing problem file", ()),
            ("adir", "a directory as the problem file", (FileSpec("adir", "dir"),)),
            ("/dev/null", "/dev/null as the problem file", ()),
            ("fifo", "a FIFO as the problem file", (FileSpec("fifo", "fifo"),)),
        ):
            inv.add(
                command,
                [arg, *base],
                desc,
                ("PROBLEM", arg, "problem"),
                files=files,
                fast=fast and arg != "fifo",
                category="problem-argument",
            )
    inv.add(
        "model",
        ["a.toml", "b.toml"],
        "two problem files",
        ("b.toml",),
        files=(FileSpec("a.toml", content=""),),
        fast=True,
    )


def common_entries(inv: Invocations) -> None:
    """Option syntax of every command, the problem argument, the group's own arguments."""
    _option_syntax_entries(inv)
    _problem_argument_entries(inv)
    inv.add("", ["bogus-command"], "an unknown command", ("bogus-command",), fast=True)
    inv.add("", ["--bogus"], "an unknown global option", ("--bogus",), fast=True)
    inv.add("", ["--version"], "--version (control)", (), expect="ok", fast=True)
    inv.add("model", ["--help"], "model --help (control)", (), expect="ok", fast=True)


# --- synthesize, margins -----------------------------------------------------

_D_ORDERS = ["1000", "-1", "", "a", "1,,2", "nan", "1.5", "1e9", "1,2,4,8,16,32,64,128"]


def synthesize_entries(inv: Invocations) -> None:
    for opt in ("--mu-points", "--max-iterations", "--samples"):
        for value in INT_COUNT:
            # No D-K step (the H-inf design alone) is a valid request, and a long one.
            if (opt, value) != ("--max-iterations", "0"):
                inv.option("synthesize", opt, [value], f"{opt} {value!r}")
    for value, expect in SEED_VALUES:
        inv.option("synthesize", "--seed", [value], f"--seed {value}", expect=expect)
    for value in _D_ORDERS:
        inv.option("synthesize", "--d-orders", [value], f"--d-orders {value!r}")
    out_folder_options(inv, "synthesize")


def margins_entries(inv: Invocations) -> None:
    for value in INT_COUNT:
        inv.option("margins", "--samples", [value], f"--samples {value!r}")
    for value, expect in SEED_VALUES:
        inv.option("margins", "--seed", [value], f"--seed {value}", expect=expect)
    out_folder_options(inv, "margins")
    controller_options(inv, "margins", controller_files())
    paths = ("nope.json", "adir", "/dev/null", "fifo", "/dev/zero")
    inv.file_options("margins", "--controller", paths, category="controller")


# --- allocate, slew, simulate ------------------------------------------------

_TORQUE = [
    (["1", "2"], "two values"),
    (["nan", "0", "0"], "nan"),
    (["inf", "0", "0"], "inf"),
    (["-inf", "0", "0"], "-inf"),
    (["1.7e308", "1.7e308", "1.7e308"], "1.7e308 on every axis"),
    (["1e300", "0", "0"], "1e300"),
    (["a", "b", "c"], "letters"),
    (["", "0", "0"], "an empty value"),
]
_VALID_TORQUE = [
    (["5e-321", "0", "0"], "5e-321 (subnormal)"),
    (["1e-15", "0", "0"], "1e-15"),
    (["0", "0", "0"], "zero"),
]
_FAILED = [
    ("0", "reject"),
    ("25", "reject"),
    ("-1", "reject"),
    ("a", "reject"),
    ("1,,2", "reject"),
    ("", "reject"),
    ("1.5", "reject"),
    ("1,1", "either"),
    (",".join(str(i) for i in range(1, 25)), "either"),
]

# CUBESAT:ENGINE pairs; the paper's CubeSats have one engine each.
_FAILED_ENGINES = [
    ("1:2", "reject"),
    ("25:1", "reject"),
    ("0:1", "reject"),
    ("1", "reject"),
    ("1:a", "reject"),
    ("", "reject"),
    ("3:1", "ok"),
]


def _allocate_demand_entries(inv: Invocations) -> None:
    """``--torque-mNm`` and ``--force-mN`` (fast: no long computation whatever it does)."""
    for values, desc in _TORQUE:
        inv.option("allocate", "--torque-mNm", values, f"--torque-mNm {desc}", fast=True)
    inv.add(
        "allocate",
        ["--torque-mNm", "1", "2", "3", "4", "--json"],
        "--torque-mNm with four values (the fourth is taken as the problem file)",
        ("4", "--torque-mNm", "PROBLEM"),
        fast=True,
    )
    for values, desc in _VALID_TORQUE:
        inv.option(
            "allocate",
            "--torque-mNm",
            values,
            f"--torque-mNm {desc}: a valid demand, thrust must be a number",
            expect="ok",
            fast=True,
            forbid=("null", "NaN", "Infinity"),
        )
    inv.add("allocate", ["--json"], "--torque-mNm missing", ("--torque-mNm",), fast=True)
    for values, desc in (
        (["nan", "0", "0"], "nan"),
        (["1e308", "0", "0"], "1e308"),
        (["1", "2"], "two values"),
    ):
        inv.option("allocate", "--force-mN", values, f"--force-mN {desc}", fast=True)


def allocate_entries(inv: Invocations) -> None:
    _allocate_demand_entries(inv)
    for value, expect in _FAILED:
        fast = value in ("0", "25", "a")
        inv.option("allocate", "--failed", [value], f"--failed {value!r}", expect=expect, fast=fast)
    for value, expect in _FAILED_ENGINES:
        fast = value in ("1:2", "25:1")
        inv.option(
            "allocate",
            "--failed-engines",
            [value],
            f"--failed-engines {value!r}",
            expect=expect,
            fast=fast,
        )
    for value in ("junk", "", "nan"):
        inv.option("allocate", "--solver", [value], f"--solver {value!r}", fast=value == "junk")
    inv.option("allocate", "--saturation", ["junk"], "--saturation junk", fast=True)
    stage_state_options(inv)


def slew_entries(inv: Invocations) -> None:
    for value in ("w", "", "xy", "+q", "nan", "0"):
        inv.option("slew", "--axis", [value], f"--axis {value!r}", fast=True)
    inv.option("slew", "--axis", ["-x"], "--axis -x (control)", expect="ok")
    for value in ("0", "-10", "181", "nan", "inf", "1e308", "abc"):
        fast = value in ("nan", "abc")
        inv.option("slew", "--angle-deg", [value], f"--angle-deg {value}", fast=fast)
    inv.option("slew", "--method", ["junk"], "--method junk", fast=True)
    inv.option("slew", "--flexible-method", ["junk"], "--flexible-method junk", fast=True)
    for opt, values in (
        ("--duration-s", DURATION),
        ("--torque-fraction", ["0", "-0.5", "1.5", "nan", "inf"]),
        ("--rate-limit-deg-s", ["0", "-1", "nan", "inf", "abc"]),
        ("--smoothing-s", ["-1", "nan", "inf", "1e12"]),
        ("--sample-s", ["0", "-1", "nan", "inf", "1e-12", "abc"]),
    ):
        for value in values:
            inv.option("slew", opt, [value], f"{opt} {value}")
    out_folder_options(inv, "slew")


def simulate_entries(inv: Invocations) -> None:
    for opt, values in (
        ("--corner", ["-1", "256", "1000000000", "nan", "abc"]),
        ("--sample", ["-1", "1000000000", "nan"]),
    ):
        for value in values:
            inv.option("simulate", opt, [value], f"{opt} {value}")
    for value, expect in SEED_VALUES:
        inv.option("simulate", "--seed", [value], f"--seed {value}", expect=expect)
    for value in DURATION:
        inv.option("simulate", "--duration-s", [value], f"--duration-s {value}")
    out_folder_options(inv, "simulate")
    controller_options(inv, "simulate", list(controller_files())[:6])
    paths = ("nope.json", "adir", "fifo")
    inv.file_options("simulate", "--controller", paths, category="controller")
    open_loop_options(inv)


# --- montecarlo, reproduce, compare ------------------------------------------

_WORKERS = [
    ("0", "reject"),
    ("-1", "reject"),
    ("nan", "reject"),
    ("abc", "reject"),
    ("1000000", "either"),
]
_SCHEDULERS = ("junk", "", "tcp://", "file:///etc/passwd", "inproc://x", "tcp://127.0.0.1:9")


def montecarlo_entries(inv: Invocations) -> None:
    for opt in ("--samples", "--max-cases"):
        for value in INT_COUNT:
            inv.option("montecarlo", opt, [value], f"{opt} {value!r}")
    for value, expect in SEED_VALUES:
        inv.option("montecarlo", "--seed", [value], f"--seed {value}", expect=expect)
    for value, expect in _WORKERS:
        inv.option("montecarlo", "--workers", [value], f"--workers {value}", expect=expect)
    for value in _SCHEDULERS:
        desc = f"--scheduler {value!r}"
        inv.option("montecarlo", "--scheduler", [value], desc, category="scheduler")
    out_folder_options(inv, "montecarlo")
    controller_options(inv, "montecarlo", ("NaN in A", "not JSON"))


def reproduce_entries(inv: Invocations) -> None:
    out_folder_options(inv, "reproduce")
    for value in ("0", "-1", "nan", "abc"):
        inv.option("reproduce", "--workers", [value], f"--workers {value}")


def compare_entries(inv: Invocations) -> None:
    inv.add(
        "compare",
        ["--out", "out", "--json"],
        "no problem file",
        ("PROBLEM_FILES", "problem"),
        fast=True,
    )
    for arg, desc, files in (
        ("nope.toml", "a missing problem file", ()),
        ("adir", "a directory", (FileSpec("adir", "dir"),)),
        ("fifo", "a FIFO", (FileSpec("fifo", "fifo"),)),
    ):
        inv.add(
            "compare",
            [SHORT_TOML, arg, "--out", "out", "--json"],
            desc,
            (arg, "PROBLEM_FILES", "problem"),
            files=files,
        )
    for value in ("junk", "", ",", "bang-bang,junk"):
        inv.option("compare", "--methods", [value], f"--methods {value!r}")
    out_folder_options(inv, "compare")
    controller_options(inv, "compare", ("not JSON",))
