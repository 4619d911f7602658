"""The one project-wide JIT decorator and the cache that keeps it safe.

Every kernel is compiled with ``cache=True``, ``nogil=True`` and
``error_model="numpy"`` (division by zero gives inf/nan instead of raising,
so that kernels stay exception-free and report problems by status codes).

Where the cache lives
---------------------
Numba's own cache sits next to each source file and is keyed by that file
alone: after a callee in another file changes (a ``git pull`` on an
editable install), a cached caller keeps running the old callee, bit for
bit. hbmfric therefore places the cache of its own files in a directory
named after a hash of all kernel sources (:func:`source_key`), so that any
edit of any kernel starts a fresh cache and a stale one can never be read
(the key is remembered between processes with the size and modification
time of every source file, :func:`remembered_source_key`):

1. ``$HBMFRIC_CACHE_DIR/<key>`` if that variable is set,
2. else ``$NUMBA_CACHE_DIR/hbmfric/<key>`` if Numba's variable is set,
3. else ``$XDG_CACHE_HOME/hbmfric/<key>`` (default ``~/.cache``).

If that directory cannot be created or written (read-only home, read-only
container), the kernels are compiled without a cache in every process and
one :class:`~hbmfric.errors.CacheWarning` says so; ``import hbmfric`` never
fails for want of a cache. Old ``<key>`` directories are not removed
automatically (another installation may still use them); delete them at
will.

The first compilation
---------------------
Compiling the kernels takes minutes on a small machine; it happens once per
installed version. So that a first run does not look hung, the first
compilation of a hbmfric kernel in a process prints one line to standard
error saying what happens, why, and that it happens once (a listener on
Numba's ``numba:compile`` event, which fires only for a real compilation,
never for a kernel loaded from the cache). ``HBMFRIC_QUIET=1`` silences it.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
import tempfile
import time
import warnings

from numba import njit
from numba.core import caching
from numba.core import event as _event

from .errors import CacheWarning

PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
"""Directory of the hbmfric package whose files use this cache."""


_FROM_IMPORT = re.compile(
    r"^[ \t]*from[ \t]+(\.*)([\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n#;]*)", re.M
)
_PLAIN_IMPORT = re.compile(r"^[ \t]*import[ \t]+([\w.]+)", re.M)


def _imports(path: str, text: str, package_dir: str) -> tuple[bool, list[str]]:
    """Scan one module's import statements: does it import Numba or ``_jit``,
    and which files of the package does it import (relative imports)?

    A textual scan (fast, unlike parsing): an import written inside a string
    can only add a file to the hash, never drop one.
    """
    uses_numba = any(
        m.group(1).split(".")[0] == "numba" for m in _PLAIN_IMPORT.finditer(text)
    )
    deps = []
    here = os.path.dirname(path)
    for m in _FROM_IMPORT.finditer(text):
        dots, module, names = m.groups()
        if not dots:
            uses_numba |= module.split(".")[0] == "numba"
            continue
        base = here
        for _ in range(len(dots) - 1):
            base = os.path.dirname(base)
        if module:
            targets = [module.split(".")]
        else:
            names = names.strip("()").replace("\n", " ")
            targets = [[n.split()[0]] for n in names.split(",") if n.strip()]
        for name in targets:
            stem = os.path.join(base, *name)
            for candidate in (stem + ".py", os.path.join(stem, "__init__.py")):
                if candidate.startswith(package_dir) and os.path.isfile(candidate):
                    deps.append(candidate)
                    uses_numba |= name[-1] == "_jit"
    return uses_numba, deps


def kernel_sources(package_dir: str = PACKAGE_DIR) -> list[str]:
    """Paths of every source file that can change compiled code.

    These are the ``.py`` files under ``package_dir`` that use Numba or the
    ``jit`` decorator, plus every package module they import (relative
    imports, followed transitively: constants and helpers that compiled code
    freezes).

    Parameters
    ----------
    package_dir : str
        Root directory of the package.

    Returns
    -------
    list of str, sorted
    """
    package_dir = os.path.abspath(package_dir)
    texts = {}
    for root, dirs, files in os.walk(package_dir):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(root, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    texts[path] = f.read()
    parsed = {}

    def parse(path):
        if path not in parsed:
            parsed[path] = _imports(path, texts[path], package_dir)
        return parsed[path]

    # Parsing is the slow part: parse only files that can import Numba or
    # _jit, and the files they import.
    todo = [
        p for p, t in texts.items() if ("numba" in t or "_jit" in t) and parse(p)[0]
    ]
    seen = set(todo)
    while todo:
        path = todo.pop()
        for dep in parse(path)[1]:
            if dep not in seen and dep in texts:
                seen.add(dep)
                todo.append(dep)
    return sorted(seen)


def source_key(package_dir: str = PACKAGE_DIR) -> str:
    """Hash of all kernel sources of the package (:func:`kernel_sources`).

    Parameters
    ----------
    package_dir : str
        Root directory of the package.

    Returns
    -------
    str
        16 hex digits; changes whenever any kernel source, or the set of
        kernel files, changes.
    """
    package_dir = os.path.abspath(package_dir)
    h = hashlib.sha256()
    for path in kernel_sources(package_dir):
        rel = os.path.relpath(path, package_dir).replace(os.sep, "/")
        with open(path, "rb") as f:
            data = f.read()
        h.update(rel.encode() + b"\0" + str(len(data)).encode() + b"\0" + data)
    return h.hexdigest()[:16]


def _stamp(package_dir: str) -> tuple[str, int]:
    """Hash of the relative path, size, modification and status-change
    times (ns) and inode of every ``.py`` file under ``package_dir``: a
    cheap fingerprint (one stat call per file, no file read) that changes
    whenever :func:`source_key` can change. The status-change time is set
    by the system on every write and cannot be set back (unlike the
    modification time, which ``cp -p`` or ``rsync -a`` preserve).

    Returns the fingerprint and the newest of those times (ns)."""
    h = hashlib.sha256()
    newest = 0
    for root, dirs, files in os.walk(package_dir):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(root, name)
                st = os.stat(path)
                newest = max(newest, st.st_mtime_ns, st.st_ctime_ns)
                rel = os.path.relpath(path, package_dir)
                h.update(
                    f"{rel}\0{st.st_size}\0{st.st_mtime_ns}\0{st.st_ctime_ns}\0"
                    f"{st.st_ino}\0".encode()
                )
    return h.hexdigest()[:16], newest


#: a fingerprint is remembered only when every file is older than this (ns):
#: file times advance by a coarse clock tick (milliseconds on Linux), so an
#: edit in the same tick as the fingerprint could keep its times and size
#: (git's "racily clean" files); two seconds later no edit can
RACY_NS = 2_000_000_000


def remembered_source_key(
    package_dir: str = PACKAGE_DIR, base: str | None = None
) -> str:
    """:func:`source_key`, remembered between processes.

    Reading and scanning every source file at each import costs about 20 ms
    on a small machine (a fiftieth of a first FRF in a fresh process); the
    key is therefore kept in ``<base>/source-key-<hash of package_dir>``
    with the :func:`_stamp` of the files it was computed from, and computed
    again only when the stamp differs (a file edited, added, removed or
    replaced changes its size or times: Python trusts the size and
    modification time for its ``.pyc`` files, Numba for its cache index;
    an edit that keeps the size within one tick of a coarse file-system
    clock would go unseen by all three). Without a writable ``base`` the
    key is computed every time.

    Parameters
    ----------
    package_dir : str
        Root directory of the package.
    base : str, optional
        Directory for the remembered key (default :func:`cache_base`).

    Returns
    -------
    str
        The same 16 hex digits as ``source_key(package_dir)``.
    """
    package_dir = os.path.abspath(package_dir)
    base = cache_base() if base is None else base
    stamp, newest = _stamp(package_dir)
    where = hashlib.sha256(package_dir.encode()).hexdigest()[:16]
    memo = os.path.join(base, f"source-key-{where}")
    try:
        with open(memo, encoding="ascii") as f:
            seen, key = f.read().split()
        if seen == stamp and re.fullmatch("[0-9a-f]{16}", key):
            return key
    except (OSError, ValueError, UnicodeDecodeError):
        pass
    key = source_key(package_dir)
    if time.time_ns() - newest < RACY_NS:
        return key  # a file edited just now: not remembered (``RACY_NS``)
    try:
        os.makedirs(base, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=base, prefix=".source-key-")
        with os.fdopen(fd, "w", encoding="ascii") as f:
            f.write(f"{stamp} {key}\n")
        os.replace(tmp, memo)  # atomic: a reader sees the old or the new line
    except OSError:
        pass
    return key


def cache_base(environ=None) -> str:
    """Directory under which the ``<key>`` cache directories live.

    Parameters
    ----------
    environ : mapping, optional
        Environment to read (default ``os.environ``).
    """
    env = os.environ if environ is None else environ
    if env.get("HBMFRIC_CACHE_DIR"):
        return os.path.abspath(os.path.expanduser(env["HBMFRIC_CACHE_DIR"]))
    if env.get("NUMBA_CACHE_DIR"):
        return os.path.join(os.path.abspath(env["NUMBA_CACHE_DIR"]), "hbmfric")
    xdg = env.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(os.path.abspath(xdg), "hbmfric")


def _writable_dir(path: str) -> str | None:
    """Create ``path`` and check that a file can be written there; return
    None on success, else the reason."""
    try:
        os.makedirs(path, exist_ok=True)
        tempfile.TemporaryFile(dir=path).close()
    except OSError as exc:
        return f"{type(exc).__name__}: {exc}"
    return None


#: cache directories already checked writable in this process
_CHECKED_PATHS: set[str] = set()


class _KeyedCacheLocator(caching._SourceFileBackedLocatorMixin, caching._CacheLocator):
    """Numba cache locator for the files of the hbmfric package only: puts
    their cache in ``CACHE_DIR/<subdirectory in the package>``."""

    def __init__(self, py_func, py_file):
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        rel = os.path.relpath(os.path.dirname(os.path.abspath(py_file)), PACKAGE_DIR)
        self._cache_path = os.path.normpath(os.path.join(CACHE_DIR, rel))

    def get_cache_path(self):
        return self._cache_path

    @classmethod
    def from_function(cls, py_func, py_file):
        if CACHE_DIR is None:
            return None
        path = os.path.abspath(py_file)
        if not path.startswith(PACKAGE_DIR + os.sep) or not os.path.isfile(path):
            return None
        self = cls(py_func, py_file)
        if self._cache_path not in _CHECKED_PATHS:
            # Numba's check (create the directory, write a temporary file)
            # once per directory and process, not once per kernel: an
            # import makes some 150 kernels in 8 directories
            try:
                self.ensure_cache_path()
            except OSError:
                return None
            _CHECKED_PATHS.add(self._cache_path)
        return self


def _register_locator() -> None:
    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
    classes = impl._locator_classes
    classes[:] = [c for c in classes if c.__name__ != _KeyedCacheLocator.__name__]
    classes.insert(0, _KeyedCacheLocator)


CACHE_DIR: str | None = os.path.join(cache_base(), remembered_source_key())
"""Directory of the compiled-kernel cache, or None if there is none."""

_reason = _writable_dir(CACHE_DIR)
if _reason is not None:
    warnings.warn(
        f"hbmfric cannot write its Numba cache to {CACHE_DIR!r} ({_reason}); "
        "kernels are compiled in every process, which takes minutes. Set "
        "HBMFRIC_CACHE_DIR to a writable directory to cache them.",
        CacheWarning,
        stacklevel=2,
    )
    CACHE_DIR = None
del _reason

CACHE: bool = CACHE_DIR is not None
"""Whether compiled kernels are cached (pass as ``cache=`` to Numba)."""

_register_locator()


class CompileNotice(_event.Listener):
    """Prints one line when the first kernel under ``prefix`` is compiled.

    Parameters
    ----------
    prefix : str
        Directory whose kernels count (the hbmfric package).
    cache_dir : str or None
        Where the compiled kernels go (None: no cache).
    stream : file-like, optional
        Where the line goes (default ``sys.stderr`` at the time of writing).
    """

    def __init__(self, prefix: str, cache_dir: str | None, stream=None) -> None:
        self.prefix = os.path.abspath(prefix) + os.sep
        self.cache_dir = cache_dir
        self.stream = stream
        self.done = False

    def message(self) -> str:
        """The line printed."""
        if self.cache_dir is None:
            where = (
                "there is no writable cache, so this happens in every process "
                "(set HBMFRIC_CACHE_DIR to a writable directory)"
            )
        else:
            where = (
                "once per installed version for each kernel: later runs load "
                f"them from {self.cache_dir}; a run that takes a path not used "
                "before compiles its kernels then (`hbmfric warmup` compiles "
                "every path ahead)"
            )
        return (
            "hbmfric: compiling the Numba kernels this run needs for the first "
            f"time (up to a few minutes on two cores); this happens {where}."
        )

    def on_start(self, event) -> None:
        if self.done:
            return
        func = getattr(event.data.get("dispatcher"), "py_func", None)
        path = getattr(getattr(func, "__code__", None), "co_filename", "")
        if not os.path.abspath(path).startswith(self.prefix):
            return
        self.done = True
        print(self.message(), file=self.stream or sys.stderr, flush=True)

    def on_end(self, event) -> None:
        pass


if not os.environ.get("HBMFRIC_QUIET"):
    _event.register("numba:compile", CompileNotice(PACKAGE_DIR, CACHE_DIR))

jit = njit(cache=CACHE, nogil=True, error_model="numpy")

#: ``jit`` for a kernel that other kernels inline (Numba IR inlining): a call
#: from compiled code compiles no separate kernel, so the caller does not
#: link in, optimise and emit once more the whole tree of kernels the
#: inlined one calls (the HBM residual under every continuation kernel: each
#: compiled kernel emits machine code for everything it links, so a chain
#: of kernels above the residual compiles the residual once per link of the
#: chain). Called from Python it compiles like any ``jit`` kernel. Use it
#: for kernels called from few sites, above the residual.
jit_inline = njit(cache=CACHE, nogil=True, error_model="numpy", inline="always")

__all__ = [
    "CACHE",
    "CACHE_DIR",
    "cache_base",
    "jit",
    "jit_inline",
    "kernel_sources",
    "remembered_source_key",
    "source_key",
]
