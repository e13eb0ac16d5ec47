"""``X…`` entries: broken ``extends`` (missing, directory, circular, FIFO, devices, huge, deep)."""

from __future__ import annotations

from collections.abc import Callable

from .entry import Entry, FileSpec
from .shipped import problems_dir
from .toml_writer import toml_string

NAMES = ("extends",)

# (description, files, expectation, names, fast)
Case = tuple[str, tuple[FileSpec, ...], str, tuple[str, ...], bool]
Child = Callable[..., str]


def _case(
    desc: str,
    *files: FileSpec,
    expect: str = "reject",
    names: tuple[str, ...] = NAMES,
    fast: bool = False,
) -> Case:
    return desc, files, expect, names, fast


def _p(content: str) -> FileSpec:
    """The problem file every run is given."""
    return FileSpec("p.toml", content=content)


def _paths_and_loops(child: Child) -> list[Case]:
    """Missing, folders, itself, circular chains."""
    return [
        _case("missing file", _p(child("nope.toml")), names=(*NAMES, "nope.toml"), fast=True),
        _case("a directory", FileSpec("sub", "dir"), _p(child("sub")), fast=True),
        _case('"" (the folder)', _p(child("")), fast=True),
        _case('"." (the folder)', _p(child("."))),
        _case("itself", _p(child("p.toml")), fast=True),
        _case(
            "circular a -> b -> a",
            FileSpec("b.toml", content=child("p.toml")),
            _p(child("b.toml")),
            fast=True,
        ),
        _case(
            "circular via a different spelling (./p.toml, sub/../p.toml)",
            FileSpec("sub", "dir"),
            FileSpec("b.toml", content=child("sub/../p.toml")),
            _p(child("./b.toml")),
        ),
    ]


def _special_files(child: Child) -> list[Case]:
    """FIFOs, devices, symlinks to them or to nothing."""
    return [
        _case("a FIFO", FileSpec("fifo", "fifo"), _p(child("fifo")), fast=True),
        _case("/dev/zero", _p(child("/dev/zero")), fast=True),
        _case("/dev/null (full problem beside)", _p(child("/dev/null", True)), fast=True),
        _case("/dev/urandom", _p(child("/dev/urandom"))),
        _case("/dev/stdin (never ends)", _p(child("/dev/stdin")), fast=True),
        _case(
            "a symlink to /dev/zero",
            FileSpec("z.toml", "symlink", "/dev/zero"),
            _p(child("z.toml")),
        ),
        _case(
            "a dangling symlink",
            FileSpec("d.toml", "symlink", "nowhere.toml"),
            _p(child("d.toml")),
            names=(*NAMES, "d.toml"),
        ),
    ]


def _large(child: Child, paper_text: str) -> list[Case]:
    """Huge files and deep chains."""
    padding = ("# padding " * 8 + "\n") * 500_000 + paper_text
    return [
        _case(
            "a 1 GiB sparse file",
            FileSpec("huge.toml", "sparse", size=1 << 30),
            _p(child("huge.toml")),
        ),
        _case(
            "a 40 MB file of comments",
            FileSpec("big.toml", "text", padding),
            _p(child("big.toml")),
        ),
        _case(
            "a chain 2000 deep",
            FileSpec("chain", "chain", size=2000),
            _p(child("chain_0.toml")),
        ),
        _case(
            "a chain 50 deep",
            FileSpec("chain", "chain", size=50),
            _p(child("chain_0.toml")),
            expect="either",
        ),
    ]


def _contents(child: Child, paper_text: str, paper_path: str) -> list[Case]:
    """Bad contents at the other end, ``extends`` not a string, and the controls."""
    negative_mass = paper_text.replace("mass_kg = 500.0", "mass_kg = -1.0")
    table = f'extends = {{ path = {toml_string(paper_path)} }}\nname = "x"\n'
    return [
        _case(
            "not valid TOML",
            FileSpec("bad.toml", content="hub = [\n"),
            _p(child("bad.toml")),
            names=(*NAMES, "bad.toml"),
            fast=True,
        ),
        _case(
            "binary bytes",
            FileSpec("bin.toml", "bytes", "\xff\xfe\x00\x01garbage"),
            _p(child("bin.toml")),
            names=(*NAMES, "bin.toml"),
        ),
        _case(
            "a file with hub.mass_kg = -1",
            FileSpec("base.toml", content=negative_mass),
            _p(child("base.toml")),
            names=("hub.mass_kg",),
            fast=True,
        ),
        _case("extends = 5", _p('extends = 5\nname = "x"\n'), fast=True),
        _case("extends = []", _p('extends = []\nname = "x"\n')),
        _case("extends = { path = ... }", _p(table)),
        _case(
            "the paper by absolute path (control)",
            _p(child(paper_path)),
            expect="ok",
            names=(),
            fast=True,
        ),
        _case(
            "a copy of the paper, relative (control)",
            FileSpec("paper.toml", content=paper_text),
            _p(child("paper.toml")),
            expect="ok",
            names=(),
        ),
    ]


def extends_entries() -> list[Entry]:
    """Broken ``extends``: missing, directory, circular, FIFO, devices, huge, deep."""
    paper_path = problems_dir() / "paper.toml"
    paper_text = paper_path.read_text(encoding="utf-8")

    def child(target: str, full: bool = False) -> str:
        head = f"extends = {toml_string(target)}\n"
        if full:  # a complete problem besides the extends
            return head + paper_text.replace('name = "paper"', 'name = "full"')
        return head + 'name = "child"\n'

    cases = [
        *_paths_and_loops(child),
        *_special_files(child),
        *_large(child, paper_text),
        *_contents(child, paper_text, str(paper_path)),
    ]
    return [
        Entry(
            id=f"X{i:03d}",
            description=f"extends -> {desc}",
            runs=(("model", "p.toml", "--json"), ("budget", "p.toml", "--json")),
            files=files,
            expect=expect,
            names=entry_names,
            fast=fast,
            category="extends",
        )
        for i, (desc, files, expect, entry_names, fast) in enumerate(cases, 1)
    ]
