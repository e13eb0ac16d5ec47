"""``casadi-debris export PROBLEM --fmu FILE.fmu`` and ``casadi_debris.export(fmu=...)``:
the same plant unit from the command and from Python, and bad input refused with exit 2."""

from __future__ import annotations

import json
import shutil
import zipfile
from pathlib import Path

import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main

pytestmark = pytest.mark.skipif(
    shutil.which("gcc") is None and shutil.which("cc") is None,
    reason="no C compiler to build the FMU's binary",
)


def test_the_command_and_the_function_write_the_same_unit(tmp_path: Path) -> None:
    runner = CliRunner()
    done = runner.invoke(main, ["export", "rigid_no_arrays", "--fmu", str(tmp_path / "a.fmu")])
    assert done.exit_code == 0, done.output
    assert "FMI 2.0 co-simulation" in done.output
    printed = runner.invoke(
        main, ["export", "rigid_no_arrays", "--fmu", str(tmp_path / "b.fmu"), "--json"]
    )
    assert printed.exit_code == 0, printed.output
    summary = json.loads(printed.output)
    plant = cd.export("rigid_no_arrays", fmu=tmp_path / "c.fmu")
    assert isinstance(plant, cd.FmuExportResult)
    from_python = json.loads(json.dumps(plant.summary.to_json()))
    varying = {"path", "export_time_s"}
    assert {k: v for k, v in summary.items() if k not in varying} == {
        k: v for k, v in from_python.items() if k not in varying
    }
    # The unit is deterministic: the three files hold the same members, byte for byte.
    members = [zipfile.ZipFile(tmp_path / f"{n}.fmu").read("modelDescription.xml") for n in "abc"]
    assert members[0] == members[1] == members[2]
    assert summary["engines"] == plant.summary.engines > 0


def test_save_copies_the_unit_into_a_run_folder(tmp_path: Path) -> None:
    plant = cd.export("rigid_no_arrays", fmu=tmp_path / "plant.fmu")
    folder = plant.save(tmp_path / "run")
    assert (folder / "plant.fmu").read_bytes() == (tmp_path / "plant.fmu").read_bytes()


@pytest.mark.parametrize(
    ("arguments", "field"),
    [
        (["--fmu", "{tmp}/plant.zip"], "fmu:"),
        (["--fmu", "{tmp}/plant.fmu", "--out", "{tmp}/folder"], "fmu:"),
        (["--fmu", "{tmp}/plant.fmu", "--controller", "{tmp}/controller.json"], "fmu:"),
    ],
)
def test_bad_input_names_the_field_and_exits_2(
    tmp_path: Path, arguments: list[str], field: str
) -> None:
    (tmp_path / "controller.json").write_text("{}")
    filled = [a.format(tmp=tmp_path) for a in arguments]
    done = CliRunner().invoke(main, ["export", "rigid_no_arrays", *filled])
    assert done.exit_code == 2, done.output
    assert field in done.output
    assert "Traceback" not in done.output
    assert not (tmp_path / "plant.fmu").exists()
    assert not (tmp_path / "folder").exists()


def test_an_existing_unit_is_kept_without_overwrite(tmp_path: Path) -> None:
    target = tmp_path / "plant.fmu"
    target.write_bytes(b"not ours")
    done = CliRunner().invoke(main, ["export", "rigid_no_arrays", "--fmu", str(target)])
    assert done.exit_code == 2, done.output
    assert "--overwrite" in done.output
    assert target.read_bytes() == b"not ours"
    again = CliRunner().invoke(
        main, ["export", "rigid_no_arrays", "--fmu", str(target), "--overwrite"]
    )
    assert again.exit_code == 0, again.output
    assert zipfile.is_zipfile(target)


def test_the_job_is_not_shadowed_by_its_package() -> None:
    import casadi_debris.codegen  # noqa: F401  (a subpackage named export would rebind cd.export)

    assert cd.export.__module__ == "casadi_debris.workflows._export"
