"""A seeded corpus of bad inputs for the ``casadi-debris`` command line (issue 11).

Families of entries, each with a short id and a description of what was done to
the input:

* ``P…`` problem files (:mod:`.problem_files`): the shipped problems
  (``paper.toml``, and the ``[simulation]`` part of ``paper_slew.toml`` and
  ``paper_pointing.toml``) flattened, one mutation applied (:mod:`.mutations`:
  deleted keys and entries of ``[[arrays]]`` and ``[[arrays.modes]]``, zero,
  negative, NaN, inf, 1e308, 10**18, numeric strings, bools, flipped switches,
  wrong lengths, wrong nesting, unknown keys, path-like ``name``, unsigned
  axes), written back as TOML; then the paper with its ``[cubesat_layout]``
  written out as the ``[[cubesats]]`` list it expands to, the list and its first
  CubeSat and engine mutated the same way. ``C…`` are the children
  (``extends``) with one of their own keys mutated and overrides of the paper's
  tables (the CubeSats and arrays a child replaces whole), ``X…`` broken
  ``extends`` (:mod:`.extends`: missing, directory, circular, FIFO, devices, a
  huge file, deep chains), ``M…`` values each in range but wrong together, the
  rules of the CubeSat list and layout, the old single ``[arrays]`` and
  ``[cubesats]`` tables, and problems that are not the paper's plant through
  the commands that fly a controller (:mod:`.semantic`), and ``S…`` broken TOML
  (:mod:`.syntax`). Each is run as ``model FILE --json`` and
  ``budget FILE --json`` (and, for ``[simulation]`` keys and names, through
  ``simulate`` with a two-second run or ``margins`` with two samples; a
  mutation that changes the plant never reaches a command that flies the
  paper's controller unless that is what the entry tests);
* ``K…`` bad invocations of every command (:mod:`.invocations`,
  :mod:`.options`, :mod:`.output_folders`, :mod:`.controllers_tables`):
  option values out of range or of the wrong type, wrong arity, missing or
  unreadable files, a file where a folder is expected and vice versa, an
  existing ``--out``, unwritable places, junk ``--scheduler`` addresses,
  unknown options.

Every entry says what it expects: ``reject`` (exit 2 and one ``error:`` line
naming the key or option), ``ok`` (a still-valid input, exit 0) or ``either``
(ambiguous: only the safety checks apply).

Each run forks after the imports (no interpreter start-up per run), chdirs into
a fresh folder that is its HOME and TMPDIR, calls the click group in-process
as the console script would, and is killed after 20 s (:mod:`.runner`,
:mod:`.child`, :mod:`.sandbox`). The parent checks (:mod:`.checks`): no
traceback, exit status not 3 (nor anything but 0 and 2), no hang, no signal,
nothing written outside the run's folder (its three parent folders are listed
before and after) and no file present before the run changed, no process left
behind, and the expectation above.

:mod:`.values` is the other corpus, run in-process by
``tests/config/test_corpus.py``: every value of the shipped problems replaced by
each of a fixed list of bad values.

Run the whole corpus and print the counts::

    python -m tests.corpus --report [--fast] [--jobs 2] [--only ID,...] [--json FILE]

List the entries (ids, fast or slow, expectation, commands)::

    python -m tests.corpus --list [--fast] [--only ID,...]

Write one entry's files into a folder and print its commands (to reproduce)::

    python -m tests.corpus --materialize P0123 /tmp/p0123
"""

from .catalogue import FAST_FILES, SEED, corpus
from .checks import TIMEOUT_S, EntryResult, RunResult, check, names_match
from .entry import Entry, FileSpec
from .repository import git_status, new_repo_files
from .runner import run_corpus
from .shipped import problems_dir
from .toml_writer import toml_dumps

__all__ = [
    "FAST_FILES",
    "SEED",
    "TIMEOUT_S",
    "Entry",
    "EntryResult",
    "FileSpec",
    "RunResult",
    "check",
    "corpus",
    "git_status",
    "names_match",
    "new_repo_files",
    "problems_dir",
    "run_corpus",
    "toml_dumps",
]
