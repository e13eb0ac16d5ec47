"""The benchmark tables of the checks against outside references: the global slew
(Bilimoria & Wie), D-K on the distillation column (dkpy) and the μ bounds."""

from __future__ import annotations

from benchmark_format import Data, _get, _label, _met, _runs, num, table

GLOBAL_SLEWS = {
    "bilimoria_wie": "Bilimoria & Wie: J = I, \\|u\\| ≤ 1, 180° about z",
    "paper_x": "paper, 180° about x",
    "paper_y": "paper, 180° about y",
    "paper_z": "paper, 180° about z",
}


def slew_global(data: Data) -> str:
    targets, reference = _get(data, "targets"), _get(data, "reference")
    rows = [
        [
            _label(name, GLOBAL_SLEWS),
            num(entry["duration_s"], 7),
            num(entry["limit_duration_s"], 5),
            f"{entry['starts_agreeing']} ({entry['starts_agreeing_direct']}) of {entry['starts']}",
            ", ".join(num(value, 6) for value in entry["local_optima_s"]),
            num(entry["verification_attitude_error_rad"], 2),
            num(entry["multistart_time_s"]),
            num(entry["refinement_time_s"]),
            num(entry["wall_time_s"]),
        ]
        for name, entry in _get(data, "slews").items()
    ]
    return table(
        [
            "slew",
            "duration [s]",
            "eigenaxis [s]",
            "starts agreeing (directly)",
            "local optima, collocation [s]",
            "verification residual [rad]",
            "multi-start [s]",
            "switch times [s]",
            "whole call [s]",
        ],
        rows,
        "lrrrlrrrr",
    ) + (
        f"\nPublished {num(reference['bilimoria_wie_s'], 5)} s (eigenaxis "
        f"{num(reference['eigenaxis_s'], 5)} s), relative error "
        f"{num(targets['benchmark_relative_error'], 2)}: within 0.05 % "
        f"{_met(targets['benchmark_met'])}; ≥ 95 % of the starts agreeing on the paper's "
        f"slews {_met(targets['agreement_met'])}; multi-start ≤ 10 s "
        f"{_met(targets['multistart_time_met'])}; "
        f"{_runs(_get(data, 'run', 'settings', 'repeat'))}.\n"
    )


MU_CONTROLLERS = {"reduced": "shipped reduced controller", "full": "full-order controller"}


def mu_bounds(data: Data) -> str:
    points = _get(data, "run", "settings", "points")
    limit = _get(data, "targets", "mu_bounds_200_s")
    rows = [
        [
            _label(name, MU_CONTROLLERS),
            num(entry["peak_upper"], 7),
            num(entry["peak_lower"], 7),
            num(entry["gap"], 2),
            num(entry["peak_rad_s"]),
            entry["upper_method"],
            num(entry["time_s_median"]),
        ]
        for name, entry in _get(data, "controllers").items()
    ]
    blocks = ", ".join(f"{kind} {size}" for kind, size in _get(data, "blocks"))
    times = [entry["time_s_median"] for entry in data["controllers"].values()]
    return table(
        ["closed loop", "μ upper", "μ lower", "gap", "peak [rad/s]", "upper by", "time [s]"],
        rows,
        "lrrrrlr",
    ) + (
        f"\nStructure {{{blocks}}}, {points} frequencies per controller: ≤ {num(limit)} s "
        f"{_met(max(times) <= limit)}.\n"
    )


def musyn_distillation(data: Data) -> str:
    rows = [
        [
            str(it["index"]),
            str(it["d_order"]),
            num(it["gamma"], 5),
            num(it["mu_peak"], 5),
            num(it["time_s"]),
        ]
        for it in _get(data, "dk_iterations")
    ]
    limit = _get(data, "targets", "synthesis_s")
    return table(["step", "D order", "γ", "μ peak", "time [s]"], rows) + (
        f"\nFinal μ {num(data['mu_peak'], 5)} against dkpy's {num(data['mu_peak_dkpy'], 5)} "
        f"(ratio {num(data['mu_ratio_to_dkpy'], 4)}), stopped: {data['stop_reason']}; "
        f"synthesis {num(data['synthesis_s'])} s, ≤ {num(limit)} s "
        f"{_met(data['synthesis_s'] <= limit)}.\n"
    )


def references(found: dict[str, Data]) -> str:
    """The three checks against outside references, one row each, from their recordings."""
    rows = []
    if "slew_global" in found:
        data = found["slew_global"]
        ours = _get(data, "slews", "bilimoria_wie", "duration_s")
        published = _get(data, "reference", "bilimoria_wie_s")
        rows.append(
            [
                "time-optimal slew, J = I, \\|u\\| ≤ 1, 180° (`slew_global`)",
                f"{num(ours, 6)} s",
                f"{num(published, 5)} s (Bilimoria & Wie 1993)",
                f"{(ours - published) / published:+.1e}",
            ]
        )
    if "musyn_distillation" in found:
        data = found["musyn_distillation"]
        rows.append(
            [
                "D-K on the distillation column (`musyn_distillation`)",
                f"μ = {num(data['mu_peak'], 4)}",
                f"μ = {num(data['mu_peak_dkpy'], 4)} (dkpy 0.1.9; "
                "Skogestad & Postlethwaite §8.12.4)",
                f"{data['mu_ratio_to_dkpy'] - 1:+.1e}",
            ]
        )
    if "mu_bounds" in found:
        entry = _get(found["mu_bounds"], "controllers", "reduced")
        rows.append(
            [
                "μ upper and lower bound, paper's closed loop (`mu_bounds`)",
                f"upper {num(entry['peak_upper'], 6)}",
                f"lower {num(entry['peak_lower'], 6)} (its own destabilising Δ)",
                f"gap {num(entry['gap'], 2)}",
            ]
        )
    return table(["check", "ours", "reference", "relative difference"], rows, "lrlr")
