"""The shipped problems the corpus mutates, parsed, and the children flattened onto the paper.

The flattening is the package's own ``extends`` merge
(:func:`casadi_debris.config.merge_problem`), not a copy of it.
:func:`paper_cubesat_list` is the paper with its ``[cubesat_layout]`` written out as
the ``[[cubesats]]`` list it expands to (the same plant).
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from casadi_debris.config import merge_problem

CHILDREN = ("paper_slew", "paper_pointing")


def problems_dir() -> Path:
    """The folder of the shipped problem files (``paper.toml`` and its children)."""
    from casadi_debris.config import default_problem_path

    return default_problem_path().parent


def load_toml(path: Path) -> dict[str, Any]:
    with path.open("rb") as handle:
        return tomllib.load(handle)


def load_shipped(base: str) -> dict[str, Any]:
    """``problems/<base>.toml`` as parsed, ``extends`` kept."""
    return load_toml(problems_dir() / f"{base}.toml")


def flattened(base: str) -> dict[str, Any]:
    """``problems/<base>.toml`` as one problem: a child merged onto the paper, ``extends`` gone.

    The result shares unchanged values with the paper's data: copy before changing it.
    """
    data = load_shipped(base)
    if "extends" not in data:
        return data
    paper = load_shipped("paper")
    return merge_problem(paper, {k: v for k, v in data.items() if k != "extends"})


def paper_cubesat_list() -> dict[str, Any]:
    """The paper with ``[cubesat_layout]`` replaced by the ``[[cubesats]]`` list it expands to.

    The same plant (:attr:`~casadi_debris.config.Problem.plant_sha256`): every
    CubeSat gives its position, mass, 3 x 3 inertia, face and its engine's
    direction as the vector the layout made (``[-1.0, -0.0, -0.0]``: the hash tells
    -0.0 from 0.0, so ``"-x"`` would be another plant to it). The first CubeSat
    gives its inertia as three principal moments and every engine key
    (``offset_m``, ``stages`` ...), so that each form and key has a node to mutate.
    """
    from casadi_debris.config import load_problem

    problem = load_problem(problems_dir() / "paper.toml")
    cubesats: list[dict[str, Any]] = []
    for cubesat in problem.cubesats:
        cubesats.append(
            {
                "position_corner_m": cubesat.position_corner_m.tolist(),
                "mass_kg": cubesat.mass_kg,
                "inertia_kgm2": cubesat.inertia_kgm2.tolist(),
                "face": cubesat.face,
                "engines": [{"direction": e.direction.tolist()} for e in cubesat.engines],
            }
        )
    first, engine = problem.cubesats[0], problem.cubesats[0].engines[0]
    cubesats[0]["inertia_kgm2"] = [float(v) for v in first.inertia_kgm2.diagonal()]
    cubesats[0]["engines"][0] = {
        "direction": engine.direction.tolist(),
        "offset_m": engine.offset_m.tolist(),
        "stages": engine.stages,
        "emitters_per_stage": engine.emitters_per_stage,
        "thrust_per_stage_mN": engine.thrust_per_stage_mN,
        "isp_s": engine.isp_s,
        "stage_life_h": engine.stage_life_h,
    }
    data: dict[str, Any] = {}
    for key, value in load_shipped("paper").items():
        if key == "cubesat_layout":
            data["cubesats"] = cubesats  # where the layout was
        else:
            data[key] = value
    return data
