"""``S…`` entries: broken TOML (truncated at seeded positions, duplicate keys, bad bytes)."""

from __future__ import annotations

import random
import tomllib

from .entry import Entry, FileSpec
from .shipped import problems_dir

# (description, the file, expectation, names)
Case = tuple[str, FileSpec, str, tuple[str, ...]]


def _truncated(text: str, rng: random.Random) -> list[Case]:
    """The paper cut at 12 seeded places; a cut that is still TOML may pass."""
    cases: list[Case] = []
    for pos in sorted(rng.sample(range(20, len(text) - 20), 12)):
        cut = text[:pos]
        try:
            tomllib.loads(cut)
        except tomllib.TOMLDecodeError:
            desc = f"truncated at character {pos}"
            cases.append((desc, FileSpec("p.toml", content=cut), "reject", ("line", "TOML")))
        else:
            desc = f"truncated at character {pos} (still TOML)"
            cases.append((desc, FileSpec("p.toml", content=cut), "either", ()))
    return cases


def _bad_bytes(text: str) -> list[Case]:
    twice = text.replace("mass_kg = 500.0", "mass_kg = 500.0\nmass_kg = 1.0")
    return [
        ("hub.mass_kg twice", FileSpec("p.toml", content=twice), "reject", ("line", "mass_kg")),
        ("invalid UTF-8", FileSpec("p.toml", "bytes", 'name = "\xff\xfe"\n'), "reject", ()),
        ("a NUL byte", FileSpec("p.toml", "bytes", "\x00" + text), "reject", ()),
        ("UTF-8 BOM in front", FileSpec("p.toml", "bytes", "\xef\xbb\xbf" + text), "either", ()),
    ]


def syntax_entries(rng: random.Random) -> list[Entry]:
    """Broken TOML: truncated at seeded positions, duplicate keys, bad UTF-8."""
    text = (problems_dir() / "paper.toml").read_text(encoding="utf-8")
    cases = [*_truncated(text, rng), *_bad_bytes(text)]
    return [
        Entry(
            id=f"S{i:03d}",
            description=f"paper.toml: {desc}",
            runs=(("model", "p.toml", "--json"), ("budget", "p.toml", "--json")),
            files=(spec,),
            expect=expect,
            names=names,
            fast=i <= 4,
            category="syntax",
        )
        for i, (desc, spec, expect, names) in enumerate(cases, 1)
    ]
