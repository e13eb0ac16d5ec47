"""Output folders: never delete what the run did not write; replace atomically; clean up."""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from casadi_debris.errors import OutputError
from casadi_debris.store import (
    MARKER_NAME,
    RunFolder,
    check_output_file,
    check_output_folder,
    clean_stale_temporaries,
    default_run_folder,
    slug,
)
from casadi_debris.store import _folders as folders


def _result(folder: Path, label: str, files: int = 3) -> None:
    """A result whose completeness can be checked: every file names the label and count."""
    for i in range(files):
        (folder / f"part{i}.txt").write_text(f"{label} {files}")


def _whole_result(folder: Path) -> str:
    """The label of a complete result in ``folder``, or fail."""
    parts = sorted(folder.glob("part*.txt"))
    assert parts, f"{folder} holds no result: {list(folder.iterdir())}"
    labels = {p.read_text() for p in parts}
    assert len(labels) == 1, labels
    label, count = labels.pop().split()
    assert len(parts) == int(count), f"{folder}: {len(parts)} of {count} files"
    assert (folder / MARKER_NAME).is_file()
    return label


@pytest.mark.parametrize(
    ("label", "expected"),
    [
        ("paper", "paper"),
        ("../../somewhere", "somewhere"),
        ("a/b\nc", "a-b-c"),
        ("..", "run"),
        ("", "run"),
        ("x" * 300, "x" * 64),
    ],
)
def test_slug_keeps_default_folders_under_runs(label: str, expected: str) -> None:
    assert slug(label) == expected
    folder = default_run_folder("margins", label)
    assert folder.parent == Path("runs") and folder.name == f"margins-{expected}"


def test_an_existing_folder_is_refused_without_overwrite(tmp_path: Path) -> None:
    target = tmp_path / "mine"
    target.mkdir()
    (target / "sentinel").write_text("keep me")
    with pytest.raises(OutputError, match=r"--out: .* exists and is not empty; pass --overwrite"):
        check_output_folder(target)
    with pytest.raises(OutputError, match="not written by casadi-debris"):
        check_output_folder(target, overwrite=True)
    with pytest.raises(OutputError, match="not written by casadi-debris"):
        RunFolder.claim(target, overwrite=True)
    assert (target / "sentinel").read_text() == "keep me"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]


def test_a_file_or_the_working_folder_is_refused(tmp_path: Path, monkeypatch) -> None:
    afile = tmp_path / "afile"
    afile.write_text("x")
    with pytest.raises(OutputError, match="exists and is not a folder"):
        check_output_folder(afile, overwrite=True)
    run = tmp_path / "run"
    with RunFolder.claim(run) as staging:
        _result(staging, "old")
    monkeypatch.chdir(run)
    with pytest.raises(OutputError, match="holds the working folder"):
        check_output_folder(".", overwrite=True)
    assert _whole_result(run) == "old"


def test_an_empty_folder_is_used_and_a_result_replaced_only_with_overwrite(tmp_path: Path) -> None:
    target = tmp_path / "run"
    target.mkdir()
    with RunFolder.claim(target, command="test") as staging:
        _result(staging, "first")
        assert not any(target.iterdir())
    assert _whole_result(target) == "first"
    assert json.loads((target / MARKER_NAME).read_text())["command"] == "test"
    with pytest.raises(OutputError, match="pass --overwrite"):
        RunFolder.claim(target)
    with RunFolder.claim(target, overwrite=True) as staging:
        _result(staging, "second", files=5)
    assert _whole_result(target) == "second"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]


@pytest.mark.parametrize("added", ["notes.txt", "sub/notes.txt", "newfolder"])
def test_a_result_holding_a_users_file_is_never_replaced(tmp_path: Path, added: str) -> None:
    target = tmp_path / "run"
    with RunFolder.claim(target) as staging:
        _result(staging, "first")
        (staging / "sub").mkdir()
    user = target / added
    if added == "newfolder":
        user.mkdir()
    else:
        user.parent.mkdir(exist_ok=True)
        user.write_text("mine")
    with pytest.raises(OutputError, match=f"holds {added}, not written by casadi-debris"):
        RunFolder.claim(target, overwrite=True)
    assert user.exists() and _whole_result(target) == "first"


def test_a_users_file_added_during_the_run_stops_the_swap(tmp_path: Path) -> None:
    target = tmp_path / "run"
    with RunFolder.claim(target) as staging:
        _result(staging, "first")
    folder = RunFolder.claim(target, overwrite=True)
    _result(folder.staging, "second")
    (target / "notes.txt").write_text("mine")
    with pytest.raises(OutputError, match="the new result is in"):
        folder.commit()
    assert (target / "notes.txt").read_text() == "mine" and _whole_result(target) == "first"
    assert _whole_result(folder.staging) == "second"


def test_a_result_whose_marker_lists_no_files_is_not_replaced(tmp_path: Path) -> None:
    target = tmp_path / "run"
    with RunFolder.claim(target) as staging:
        _result(staging, "first")
    marker = json.loads((target / MARKER_NAME).read_text())
    del marker["files"]
    (target / MARKER_NAME).write_text(json.dumps(marker))
    with pytest.raises(OutputError, match="does not list the files its run wrote"):
        RunFolder.claim(target, overwrite=True)
    assert _whole_result(target) == "first"


def test_an_error_leaves_the_old_result_and_no_temporaries(tmp_path: Path) -> None:
    target = tmp_path / "run"
    with RunFolder.claim(target) as staging:
        _result(staging, "old")
    with pytest.raises(KeyboardInterrupt), RunFolder.claim(target, overwrite=True) as staging:
        _result(staging, "new", files=1)
        raise KeyboardInterrupt
    assert _whole_result(target) == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]


def test_an_unwritable_place_is_refused_before_work(tmp_path: Path) -> None:
    if os.geteuid() == 0:
        pytest.skip("root writes everywhere")
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        with pytest.raises(OutputError, match="cannot write"):
            check_output_folder(locked / "run")
    finally:
        locked.chmod(0o700)


def test_no_room_is_refused_before_work(tmp_path: Path) -> None:
    with pytest.raises(OutputError, match="MiB free"):
        check_output_folder(tmp_path / "run", expected_bytes=2**62)


def test_an_existing_file_is_refused_without_overwrite(tmp_path: Path) -> None:
    target = tmp_path / "controller.json"
    target.write_text("{}")
    with pytest.raises(OutputError, match="exists; pass --overwrite"):
        check_output_file(target)
    assert check_output_file(target, overwrite=True) == target
    with pytest.raises(OutputError, match="is a folder"):
        check_output_file(tmp_path, overwrite=True)


def test_temporaries_of_dead_processes_are_cleaned_and_live_ones_kept(tmp_path: Path) -> None:
    target = tmp_path / "run"
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        check=True,
        capture_output=True,
        text=True,
    )
    dead_pid = int(dead.stdout)
    stale = tmp_path / f".run.casadi-debris-{dead_pid}-00ff.new"
    stale.mkdir()
    (stale / "half.csv").write_text("t,")
    stale_file = tmp_path / f".run.casadi-debris-{dead_pid}-0aff.tmp"
    stale_file.write_text("{")
    live = tmp_path / f".run.casadi-debris-{os.getpid()}-00aa.new"
    live.mkdir()
    other = tmp_path / f".other.casadi-debris-{dead_pid}-00ff.new"
    other.mkdir()
    removed = clean_stale_temporaries(target)
    assert sorted(removed) == sorted([stale, stale_file])
    assert live.exists() and other.exists() and not stale.exists()


# ----------------------------------------------------------------------------- kills

_WRITER = textwrap.dedent(
    """
    import os, sys
    from pathlib import Path
    from casadi_debris.store import _folders as folders
    target, label, files, mode, die_at = sys.argv[1:]
    files, die_at = int(files), int(die_at)
    calls = {"n": 0}
    def dying(function):
        def wrapped(*args, **kwargs):
            calls["n"] += 1
            if calls["n"] == die_at:
                os.kill(os.getpid(), 9)
            result = function(*args, **kwargs)
            calls["n"] += 1
            if calls["n"] == die_at:
                os.kill(os.getpid(), 9)
            return result
        return wrapped
    if mode == "rename":
        folders._EXCHANGE = None
    os.rename = dying(os.rename)
    folders._exchange = dying(folders._exchange)
    folders.shutil.rmtree = dying(folders.shutil.rmtree)
    with folders.RunFolder.claim(target, overwrite=True) as staging:
        for i in range(files):
            (staging / f"part{i}.txt").write_text(f"{label} {files}")
    """
)


def _write_in_child(target: Path, label: str, files: int, mode: str, die_at: int) -> int:
    return subprocess.run(
        [sys.executable, "-c", _WRITER, str(target), label, str(files), mode, str(die_at)],
        check=False,
    ).returncode


@pytest.mark.parametrize("mode", ["exchange", "rename"])
def test_a_kill_at_every_step_of_the_swap_leaves_one_whole_result(tmp_path: Path, mode) -> None:
    if mode == "exchange" and folders._EXCHANGE is None:
        pytest.skip("no renameat2 here")
    target = tmp_path / "run"
    with RunFolder.claim(target) as staging:
        _result(staging, "old")
    seen = set()
    for die_at in range(1, 12):
        code = _write_in_child(target, f"new{die_at}", 4, mode, die_at)
        clean_stale_temporaries(target)  # what the next run in this place does first
        label = _whole_result(target)
        seen.add(label if label == "old" else "new")
        assert sorted(p.name for p in tmp_path.iterdir()) == ["run"], (die_at, code)
        if code == 0:
            break
        with RunFolder.claim(target, overwrite=True) as staging:
            _result(staging, "old")
    assert seen == {"old", "new"}, seen


def test_a_kill_at_random_moments_leaves_one_whole_result(tmp_path: Path) -> None:
    target = tmp_path / "run"
    with RunFolder.claim(target) as staging:
        _result(staging, "old")
    rng = random.Random(20261124)
    script = textwrap.dedent(
        """
        import sys
        from casadi_debris.store._folders import RunFolder
        with RunFolder.claim(sys.argv[1], overwrite=True) as staging:
            for i in range(400):
                (staging / f"part{i}.txt").write_text(f"{sys.argv[2]} 400")
        """
    )
    labels = []
    for attempt in range(12):
        child = subprocess.Popen([sys.executable, "-c", script, str(target), f"new{attempt}"])
        time.sleep(rng.uniform(0.2, 1.2))
        child.send_signal(signal.SIGKILL)
        child.wait()
        clean_stale_temporaries(target)
        labels.append(_whole_result(target))
        assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]
    assert labels, labels
