"""The command line every benchmark script starts with (benchmarks/recording.py)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture(scope="module")
def recording():
    spec = importlib.util.spec_from_file_location("recording", BENCHMARKS / "recording.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _start(recording, argv: list[str]):
    return recording.start_benchmark(
        "demo",
        "a demo benchmark",
        quick="2 repeats",
        full={"repeat": 15, "scale": 1.5},
        reduced={"repeat": 2, "scale": 0.5},
        arguments={
            "--repeat": {"type": int, "help": "repeats (15)"},
            "--scale": {"type": float},
            "--workers": {"default": "1,2"},
        },
        argv=argv,
    )


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        ([], {"repeat": 15, "scale": 1.5}),
        (["--quick"], {"repeat": 2, "scale": 0.5}),
        (["--quick", "--repeat", "7"], {"repeat": 7, "scale": 0.5}),
        (["--scale", "3"], {"repeat": 15, "scale": 3.0}),
    ],
)
def test_settings_come_from_the_command_line_else_the_full_or_quick_run(
    recording, argv: list[str], expected: dict
) -> None:
    args, run, settings = _start(recording, argv)
    assert settings == expected
    assert (args.repeat, args.scale) == (expected["repeat"], expected["scale"])
    assert args.workers == "1,2"  # the benchmark's own option, not a setting
    assert run.name == "demo" and run.args is args


def test_the_recording_options_follow_the_benchmarks_own(recording, tmp_path) -> None:
    args, _, _ = _start(recording, ["--record", "--out", str(tmp_path / "x.json"), "--note", "n"])
    assert args.record and args.out == tmp_path / "x.json" and args.note == "n"
    with pytest.raises(SystemExit):
        _start(recording, ["--bogus"])


def test_the_own_cpu_time_counts_this_process(recording) -> None:
    before = recording.own_cpu_s()
    sum(i * i for i in range(200_000))
    assert recording.own_cpu_s() > before
