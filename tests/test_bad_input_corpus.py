"""Bad input through the command line: no traceback, no exit 3, no hang, nothing written outside.

The corpus is generated (seeded) by the package ``tests/corpus/``: mutated
problem files and bad invocations of every command, each entry a test id. Every
entry runs in a forked child with a timeout; the checks are listed there. The
fast subset (about 190 problem files and 70 invocations that fail before any
long computation) is in the default selection; the whole corpus is ``slow``::

    pytest tests/test_bad_input_corpus.py -m slow

The counts for the whole corpus: ``python -m tests.corpus --report``.
"""

from __future__ import annotations

import tomllib
from collections import Counter

import pytest

from corpus import (
    Entry,
    EntryResult,
    corpus,
    git_status,
    new_repo_files,
    problems_dir,
    run_corpus,
    toml_dumps,
)

ENTRIES = corpus()
FAST = [e for e in ENTRIES if e.fast]
JOBS = 2


@pytest.fixture(scope="module")
def corpus_run(request: pytest.FixtureRequest) -> tuple[dict[str, EntryResult], list[str]]:
    """Run the entries selected in this session, once, two at a time."""
    wanted: dict[str, Entry] = {}
    for item in request.session.items:
        callspec = getattr(item, "callspec", None)
        if item.module is request.module and callspec is not None and "entry" in callspec.params:
            entry = callspec.params["entry"]
            wanted[entry.id] = entry
    before = git_status()
    results = run_corpus(list(wanted.values()), jobs=JOBS)
    repo_new = new_repo_files(before, git_status())
    return {r.entry.id: r for r in results}, repo_new


def _explain(result: EntryResult) -> str:
    entry = result.entry
    lines = [
        f"{entry.id}: {entry.description} (expected: {entry.expect})",
        *(f"  $ {command}" for command in entry.commands()),
        "problems:",
        *(f"  - {problem}" for problem in result.problems),
    ]
    for run in result.runs:
        tail = (run.stderr.strip().splitlines() or [""])[-3:]
        lines.append(f"  [{' '.join(run.args)}] exit {run.code}; stderr: {' | '.join(tail)[:400]}")
    lines.append(f"  reproduce: python -m tests.corpus --materialize {entry.id} DIR")
    return "\n".join(lines)


def _check(entry: Entry, corpus_run: tuple[dict[str, EntryResult], list[str]]) -> None:
    results, _ = corpus_run
    result = results[entry.id]
    assert result.ok, _explain(result)


@pytest.mark.parametrize("entry", FAST, ids=lambda e: e.id)
def test_bad_input_fast(entry: Entry, corpus_run) -> None:
    _check(entry, corpus_run)


@pytest.mark.slow
@pytest.mark.parametrize("entry", ENTRIES, ids=lambda e: e.id)
def test_bad_input_full(entry: Entry, corpus_run) -> None:
    _check(entry, corpus_run)


def test_no_file_written_in_the_repository(corpus_run) -> None:
    _, repo_new = corpus_run
    assert not repo_new, f"new in `git status` while the corpus ran: {repo_new}"


def test_corpus_is_large_seeded_and_covers_every_command() -> None:
    files = [e for e in ENTRIES if e.id[0] in "PCXMS"]
    invocations = [e for e in ENTRIES if e.id[0] == "K"]
    assert len(files) >= 1000
    assert len(invocations) >= 200
    assert 100 <= sum(e.fast for e in files) <= 200
    assert 30 <= sum(e.fast for e in invocations) <= 80
    again = corpus()
    assert [(e.id, e.description, e.files) for e in again] == [
        (e.id, e.description, e.files) for e in ENTRIES
    ]
    commands = Counter(e.runs[0][0] for e in invocations)
    for command in (
        "model",
        "budget",
        "synthesize",
        "margins",
        "allocate",
        "slew",
        "simulate",
        "montecarlo",
        "reproduce",
        "compare",
    ):
        assert commands[command] >= 3, command
    assert len({e.id for e in ENTRIES}) == len(ENTRIES)


def _numbers(data: object, path: tuple = ()) -> list[tuple]:
    """Paths of every number in parsed TOML (list indices included)."""
    if isinstance(data, dict):
        return [p for key, value in data.items() for p in _numbers(value, (*path, key))]
    if isinstance(data, list):
        return [p for i, value in enumerate(data) for p in _numbers(value, (*path, i))]
    return [path] if isinstance(data, int | float) and not isinstance(data, bool) else []


def test_every_number_of_the_paper_and_of_a_cubesat_list_is_mutated() -> None:
    """Every number of paper.toml and of the list's first CubeSat is NaN in some ``P`` entry.

    The numbers include ``arrays[1].modes[2].omega_rad_s``, ``cubesat_layout.mass_kg``,
    ``requirements.pointing_arcsec`` and ``cubesats[0].engines[0].isp_s``; each
    ``[[arrays]]`` entry and a mode are deleted too.
    """
    from corpus.expectations import dotted
    from corpus.shipped import load_shipped, paper_cubesat_list

    descriptions = {e.description for e in ENTRIES if e.id[0] == "P"}
    paper = load_shipped("paper")
    wanted = [f"paper.toml: {dotted(p)} = nan" for p in _numbers(paper)]
    cubesat = paper_cubesat_list()["cubesats"][0]
    wanted += [
        f"paper.toml, CubeSats as a list: {dotted(('cubesats', 0, *p))} = nan"
        for p in _numbers(cubesat)
    ]
    wanted += [f"paper.toml: arrays[{i}] deleted" for i in range(len(paper["arrays"]))]
    wanted += ["paper.toml: arrays[1].modes[2] deleted", "paper.toml: arrays = []"]
    assert not [w for w in wanted if w not in descriptions]
    for key in ("cubesat_layout.per_face", "requirements.slew_error_deg", "arrays[1].direction"):
        assert any(key in d for d in descriptions), key


def test_toml_writer_round_trips_the_shipped_problems() -> None:
    for path in sorted(problems_dir().rglob("*.toml")):  # the gallery's [[cubesats.engines]] too
        with path.open("rb") as handle:
            data = tomllib.load(handle)
        assert tomllib.loads(toml_dumps(data)) == data
    odd = {"a": 'x\n"y"\\\x00\x7f', "b": [1, 2.5, True], "t": {"u": [{"v": 1}], "w": {}}}
    assert tomllib.loads(toml_dumps(odd)) == odd
    nested = {"a": [{"b": {"c": 1}, "d": [{"e": [{"f": 2}]}], "g": [1, {"h": 3}]}], "i": []}
    assert tomllib.loads(toml_dumps(nested)) == nested
