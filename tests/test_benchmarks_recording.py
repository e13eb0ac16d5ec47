"""The command line every benchmark script starts with (benchmarks/recording.py)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture(scope="module")
def recording():
    name = "benchmarks_recording"
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / "recording.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # its dataclass looks its module up by name
    spec.loader.exec_module(module)
    yield module
    del sys.modules[name]


def _start(recording, argv: list[str]):
    options = {
        "--repeat": recording.Setting(15, 2, "repeats (15)"),
        "--workers": {"default": "1,2"},
        "--scale": recording.Setting(1.5, 0.5, "scale (1.5)"),
        "--slews": recording.Setting("a,b", "a", "slews (all)"),
    }
    return recording.start_benchmark("demo", "a demo benchmark", "2 repeats", options, argv=argv)


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        ([], {"repeat": 15, "scale": 1.5, "slews": "a,b"}),
        (["--quick"], {"repeat": 2, "scale": 0.5, "slews": "a"}),
        (["--quick", "--repeat", "7"], {"repeat": 7, "scale": 0.5, "slews": "a"}),
        (["--scale", "3", "--slews", "b"], {"repeat": 15, "scale": 3.0, "slews": "b"}),
    ],
)
def test_settings_come_from_the_command_line_else_the_full_or_quick_run(
    recording, argv: list[str], expected: dict
) -> None:
    args, run, settings = _start(recording, argv)
    assert settings == expected
    assert list(settings) == ["repeat", "scale", "slews"]  # the options' order
    assert (args.repeat, args.scale) == (expected["repeat"], expected["scale"])
    assert args.workers == "1,2"  # the benchmark's own option, not a setting
    assert run.name == "demo" and run.args is args


def test_a_setting_takes_the_type_of_its_full_value(recording) -> None:
    args, _, _ = _start(recording, ["--repeat", "4", "--scale", "2"])
    assert isinstance(args.repeat, int) and isinstance(args.scale, float)
    with pytest.raises(SystemExit):
        _start(recording, ["--repeat", "2.5"])


def test_the_recording_options_follow_the_benchmarks_own(recording, tmp_path) -> None:
    args, _, _ = _start(recording, ["--record", "--out", str(tmp_path / "x.json"), "--note", "n"])
    assert args.record and args.out == tmp_path / "x.json" and args.note == "n"
    with pytest.raises(SystemExit):
        _start(recording, ["--bogus"])


def test_the_own_cpu_time_counts_this_process(recording) -> None:
    before = recording.own_cpu_s()
    sum(i * i for i in range(200_000))
    assert recording.own_cpu_s() > before
