"""CasADi Functions compiled to C once per machine, kept on disk by content hash.

A Function's C (CasADi's code generator, the code its own JIT would compile)
is built by the system's C compiler into a shared library and loaded with
``casadi.external``. The library's name is a hash of everything that decides
its machine code: the C source, the compiler command and the compiler's
version, the CasADi version and the platform. Another process that needs the
same Function finds it and loads it in milliseconds instead of compiling it
again (seconds).

The cache folder is ``platformdirs.user_cache_dir("casadi_debris")/jit``, or
``$CASADI_DEBRIS_JIT_CACHE`` when set. It holds

- ``<key>.<digest>.so``: a library; ``key`` hashes its inputs and ``digest``
  its own bytes, so a damaged file (truncated, overwritten) is found before it
  is loaded, removed and compiled again;
- ``<key>.<random>.tmp``: a compile under way (one whose process was killed is
  removed after an hour by the next compile);
- ``<key>.lock``, while ``key`` compiles: the other processes that need it wait
  for it and load the library instead of compiling it too (an advisory ``flock``,
  released when its holder ends, however it ends).

A library is compiled into a temporary file of the same folder and moved into
place with ``os.replace``: a reader sees a whole library or none, and two
processes that compile the same Function at once both leave a valid one. An
entry is never stale (any change of its inputs is another key), so the cache
needs no cleaning to stay correct; deleting the folder clears it. Nothing is
written outside the folder: the compiler's own temporaries go there too.
"""

from __future__ import annotations

import contextlib
import fcntl
import functools
import hashlib
import logging
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from pathlib import Path

import casadi as ca
import platformdirs

from casadi_debris.errors import CompileError

CACHE_ENV = "CASADI_DEBRIS_JIT_CACHE"
# What CasADi's own JIT passes: internal names get a fixed prefix instead of
# random ones, so that the same Function always gives the same C (and key).
CODEGEN_OPTIONS = {"prefix": "jit"}
# The C comes on the compiler's standard input: no source file to write or clean.
LIBRARY_FLAGS = ("-fPIC", "-shared", "-x", "c", "-")
SUFFIX = ".so"
LOCK_SUFFIX = ".lock"
KEY_CHARS = 32
DIGEST_CHARS = 16
STALE_TEMPORARY_S = 3600.0
COMPILE_TIMEOUT_S = 900.0

LOGGER = logging.getLogger(__name__)


def cache_folder() -> Path:
    """The folder of the compiled libraries (``$CASADI_DEBRIS_JIT_CACHE`` or the user cache)."""
    given = os.environ.get(CACHE_ENV)
    if given:
        return Path(given)
    return Path(platformdirs.user_cache_dir("casadi_debris")) / "jit"


def compiled_function(
    function: ca.Function, compiler: str, flags: Sequence[str] = ("-O2",)
) -> ca.Function:
    """``function`` as compiled C: loaded from the cache, or compiled into it first.

    Parameters
    ----------
    function : casadi.Function
        Any Function CasADi can generate C for.
    compiler : str
        The C compiler (a path or a name on ``PATH``), called as
        ``compiler *flags -fPIC -shared -x c - -o library``.
    flags : sequence of str
        Compiler flags (optimisation level ...); part of the cache key.

    Returns
    -------
    casadi.Function
        An external Function of the same name, inputs and outputs.

    Raises
    ------
    CompileError
        The cache folder cannot be written, the compiler fails, or the
        compiled library does not load.
    """
    name = function.name()
    path = compiled_library(function, compiler, flags)
    try:
        return ca.external(name, str(path))
    except RuntimeError as exc:
        raise CompileError(f"the library compiled for {name!r} does not load: {exc}") from exc


def compiled_library(function: ca.Function, compiler: str, flags: Sequence[str] = ("-O2",)) -> Path:
    """Path of the shared library of ``function``'s C in the cache (compiled into it if needed).

    The library exports CasADi's C interface of generated code under the
    Function's name (``name``, ``name_work``, ``name_checkout`` ...): load it
    with ``casadi.external`` (:func:`compiled_function`) or call it directly
    (:class:`~casadi_debris.simulation._native.NativeFunction`).

    Parameters and errors (:class:`CompileError`) are those of :func:`compiled_function`.
    """
    name = function.name()
    try:
        source = c_source(function)
    except RuntimeError as exc:
        raise CompileError(f"CasADi cannot generate C for {name!r}: {exc}") from exc
    command = [compiler, *flags, *LIBRARY_FLAGS]
    key = cache_key(source, command)
    folder = cache_folder()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CompileError(
            f"the JIT cache folder {folder} cannot be created ({exc}); "
            f"set {CACHE_ENV} to a writable folder"
        ) from exc
    found = _cached(name, folder, key)
    if found is not None:
        return found
    # One compile per key at a time: the processes that need the same library at once (a
    # campaign's workers, parallel test runs) wait for the first instead of compiling it too.
    with _compile_lock(folder, key):
        found = _cached(name, folder, key)
        if found is not None:
            return found
        LOGGER.info("JIT cache miss: compiling %s (%s) into %s", name, " ".join(command), folder)
        started = time.perf_counter()
        path = _compile_into(folder, key, source, command)
    LOGGER.info("JIT cache: %s compiled in %.1f s", path.name, time.perf_counter() - started)
    return path


def _cached(name: str, folder: Path, key: str) -> Path | None:
    """The library of ``key`` in ``folder`` if one is there, whole and loadable."""
    for path in sorted(folder.glob(f"{key}.*{SUFFIX}")):
        if _load_checked(name, path) is not None:
            LOGGER.info("JIT cache hit: %s loaded from %s", name, path)
            return path
    return None


@contextlib.contextmanager
def _compile_lock(folder: Path, key: str) -> Iterator[None]:
    """Hold ``folder/<key>.lock`` (an advisory lock, released when its process ends, however).

    The file is removed by its holder when done: a process that waited on it looks
    for the library again, and a process that comes later finds the library first.
    """
    path = folder / f"{key}{LOCK_SUFFIX}"
    try:
        handle = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise CompileError(f"the JIT cache folder {folder} cannot be written: {exc}") from exc
    try:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            with contextlib.suppress(OSError):
                path.unlink()
    finally:
        os.close(handle)  # releases the lock


def c_source(function: ca.Function) -> str:
    """The C that CasADi's code generator writes for ``function`` (one translation unit)."""
    generator = ca.CodeGenerator(function.name(), CODEGEN_OPTIONS)
    generator.add(function)
    return str(generator.dump())


def cache_key(source: str, command: Sequence[str]) -> str:
    """Hash of the C source, compiler command and version, CasADi version and platform."""
    digest = hashlib.sha256()
    parts = (
        source,
        "\0".join(command),
        compiler_version(command[0]),
        ca.CasadiMeta.version(),
        ca.CasadiMeta.git_revision(),
        sys.platform,
        platform.machine(),
    )
    for part in parts:
        encoded = part.encode()
        # Length-prefixed: no two different lists of parts hash alike.
        digest.update(f"{len(encoded)}:".encode() + encoded)
    return digest.hexdigest()[:KEY_CHARS]


@functools.cache
def compiler_version(compiler: str) -> str:
    """``compiler --version`` (empty when it cannot be asked): an upgrade is another key."""
    try:
        answer = subprocess.run(
            [compiler, "--version"], capture_output=True, text=True, timeout=60, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return ""
    return answer.stdout.strip()


def _load_checked(name: str, path: Path) -> ca.Function | None:
    """The library at ``path`` if its bytes match its name and it loads; else removed, None."""
    try:
        data = path.read_bytes()
    except OSError:
        return None  # removed meanwhile by another process that found it damaged
    expected = path.name.removesuffix(SUFFIX).rpartition(".")[2]
    if _content_digest(data) != expected:
        reason = "its contents do not match their hash"
    else:
        try:
            return ca.external(name, str(path))
        except RuntimeError as exc:
            reason = f"it does not load ({exc})"
    LOGGER.warning("JIT cache: %s is damaged (%s); it is compiled again", path, reason)
    path.unlink(missing_ok=True)
    return None


def _compile_into(folder: Path, key: str, source: str, command: Sequence[str]) -> Path:
    """Compile ``source`` into ``folder/<key>.<digest>.so`` (atomically) and return its path."""
    _remove_stale_temporaries(folder)
    handle, name = tempfile.mkstemp(dir=folder, prefix=f"{key}.", suffix=".tmp")
    os.close(handle)
    temporary = Path(name)
    # The compiler's own temporaries (assembly, object) go to the cache folder too.
    environment = {**os.environ, "TMPDIR": str(folder), "TMP": str(folder), "TEMP": str(folder)}
    try:
        try:
            finished = subprocess.run(
                [*command, "-o", str(temporary)],
                input=source,
                capture_output=True,
                text=True,
                env=environment,
                timeout=COMPILE_TIMEOUT_S,
                check=False,
            )
        except (OSError, subprocess.SubprocessError) as exc:
            raise CompileError(f"{command[0]} cannot be run: {exc}") from exc
        if finished.returncode != 0:
            raise CompileError(
                f"{command[0]} failed (exit status {finished.returncode}): "
                f"{finished.stderr.strip()[-2000:]}"
            )
        path = folder / f"{key}.{_content_digest(temporary.read_bytes())}{SUFFIX}"
        os.replace(temporary, path)
    except OSError as exc:
        raise CompileError(f"the compiled library cannot be written to {folder}: {exc}") from exc
    finally:
        temporary.unlink(missing_ok=True)
    return path


def _content_digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:DIGEST_CHARS]


def _remove_stale_temporaries(folder: Path) -> None:
    """Remove the temporaries of compiles whose process was killed (older than an hour)."""
    now = time.time()
    for temporary in folder.glob("*.tmp"):
        try:
            if now - temporary.stat().st_mtime > STALE_TEMPORARY_S:
                temporary.unlink()
        except OSError:
            continue  # removed meanwhile by another process
