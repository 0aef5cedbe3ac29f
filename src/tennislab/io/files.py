"""Files that tennislab writes and reads: checked before the work, written atomically, readable by others.

* :func:`check_output_path` / :func:`check_output_dir` - validate an output path *before* any work
  (the parent is an existing, writable directory, not a regular file; the name is not too long; the
  extension is one the writer supports), so that a bad ``--plot`` or ``--csv`` fails in one line and
  leaves nothing behind.
* :func:`safe_basename` - a file name that came from data (a database, a drill file) reduced to a plain
  base name: never a path, never hidden, never too long.
* :func:`atomic_path` / :func:`atomic_write` - write to a temporary name in the destination directory,
  flush it to disk, give it the permissions a new file of the user gets (``0666 & ~umask``, typically
  0644; a plain temporary file would be owner-only, 0600) and rename it into place (``os.replace`` is
  atomic on POSIX and Windows): nothing half-written on error or interruption.
* :func:`read_text` - bounded UTF-8 reading for the readers of :mod:`tennislab.io`.

Errors are :class:`~tennislab.errors.InputError` whose message starts with the parameter's name
(``plot: ...``); the CLI turns it into the flag (``--plot: ...``).
"""

from __future__ import annotations

import errno
import os
import re
import tempfile
import unicodedata

from tennislab.errors import InputError

#: longest file-name component accepted when the file system does not say [bytes] (ext4, APFS, NTFS)
NAME_MAX = 255


def _name_max(directory: str) -> int:
    try:
        return int(os.pathconf(directory, "PC_NAME_MAX"))
    except (AttributeError, OSError, ValueError):
        return NAME_MAX


def current_umask() -> int:
    """The process's file-mode creation mask (read from ``/proc`` where possible: setting and
    restoring it with :func:`os.umask` is not thread-safe)."""
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as fh:
            for line in fh:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def new_file_mode() -> int:
    """Permissions of a new regular file of this user: ``0o666 & ~umask`` (0644 with the usual umask 022)."""
    return 0o666 & ~current_umask()


def _nearest_existing(path: str) -> str:
    """``path`` or its nearest ancestor that exists (as seen through symlinks)."""
    p = path
    while not os.path.lexists(p):
        parent = os.path.dirname(p)
        if parent == p:
            break
        p = parent
    return p


def _check_directory(param: str, shown: str, directory: str, *, create: bool) -> None:
    """The directory that will hold an output exists (or, with ``create``, can be made) and is writable."""
    existing = _nearest_existing(directory)
    if os.path.exists(existing) and not os.path.isdir(existing):
        raise InputError(f"{param}: {shown}: {existing} is a file, not a directory")
    if existing != directory and not create:
        raise InputError(f"{param}: {shown}: directory {directory} does not exist")
    if not os.path.isdir(existing):  # a dangling symlink
        raise InputError(f"{param}: {shown}: {existing} is not a directory")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise InputError(f"{param}: {shown}: directory {existing} is not writable")
    limit = _name_max(existing)
    rest = os.path.relpath(directory, existing) if existing != directory else ""
    for part in rest.split(os.sep) if rest else ():
        if len(os.fsencode(part)) > limit:
            raise InputError(f"{param}: {shown}: a directory name is {len(part)} characters long (limit {limit} bytes)")


def check_output_path(param: str, path, suffixes=None, *, create_dirs: bool = False) -> str:
    """Validate the output file ``path`` before any work is done; returns it (as a ``str``).

    The parent directory must exist and be writable (with ``create_dirs``: or be creatable, its
    nearest existing ancestor a writable directory; the writer makes it), the path must not name a
    directory, the file name must fit the file system (``NAME_MAX``, 255 bytes), and with
    ``suffixes`` (e.g. ``(".png", ".pdf")``, case-insensitive) its extension must be one of them.
    An existing file is replaced. Raises :class:`InputError` ``"param: ..."`` (one line).
    """
    if path is None:
        raise InputError(f"{param}: expected a file name")
    p = os.fspath(path)
    if not isinstance(p, str):
        p = os.fsdecode(p)
    if p == "" or p.strip() == "":
        raise InputError(f"{param}: expected a file name, got an empty string")
    if "\x00" in p:
        raise InputError(f"{param}: the file name contains a NUL character")
    if p.endswith(("/", os.sep)) or os.path.isdir(p):
        raise InputError(f"{param}: {p} is a directory, expected a file name")
    full = os.path.abspath(p)
    directory, name = os.path.split(full)
    _check_directory(param, p, directory, create=create_dirs)
    limit = _name_max(_nearest_existing(directory))
    if len(os.fsencode(name)) > limit:
        raise InputError(f"{param}: the file name is {len(name)} characters long (limit {limit} bytes)")
    if suffixes is not None:
        allowed = tuple(s.lower() for s in suffixes)
        ext = os.path.splitext(name)[1].lower()
        if ext not in allowed:
            got = f"'{ext}'" if ext else "no extension"
            raise InputError(f"{param}: {p}: unsupported file type ({got}); allowed: {', '.join(allowed)}")
    if os.path.lexists(full) and not os.access(full, os.W_OK) and not os.path.islink(full):
        raise InputError(f"{param}: {p}: the existing file is not writable")
    return p


def check_output_dir(param: str, path, *, create: bool = True) -> str:
    """Validate the output directory ``path`` before any work; returns it (as a ``str``).

    An existing directory must be writable; a missing one must be creatable (``create``: its nearest
    existing ancestor is a writable directory, not a file) - it is created by the writer, not here.
    """
    if path is None:
        raise InputError(f"{param}: expected a directory")
    p = os.fspath(path)
    if not isinstance(p, str):
        p = os.fsdecode(p)
    if p.strip() == "":
        raise InputError(f"{param}: expected a directory, got an empty string")
    if "\x00" in p:
        raise InputError(f"{param}: the directory name contains a NUL character")
    full = os.path.abspath(p)
    if os.path.exists(full) and not os.path.isdir(full):
        raise InputError(f"{param}: {p} is a file, expected a directory")
    _check_directory(param, p, full, create=create)
    return p


_UNSAFE = re.compile(r"[^\w.\- ]+")
_RESERVED = {"con", "prn", "aux", "nul", *(f"com{i}" for i in range(1, 10)), *(f"lpt{i}" for i in range(1, 10))}


def safe_basename(name, default: str = "output", max_bytes: int = 200) -> str:
    """A file name that came from data, reduced to a safe base name in the working folder.

    Only the last component of a path is kept (``/`` and ``\\`` both separate), control and shell
    characters become ``_``, leading dots are dropped (no hidden files, never ``..``), names reserved
    on Windows get a ``_`` prefix, and the result is cut to ``max_bytes`` bytes keeping its extension.
    An empty result gives ``default``. Examples: ``"../../etc/passwd"`` -> ``"passwd"``,
    ``"/abs/drill.yaml"`` -> ``"drill.yaml"``, ``"..."`` -> ``"output"``.
    """
    s = unicodedata.normalize("NFC", str(name))
    s = re.split(r"[/\\]", s)[-1]
    s = "".join(ch if unicodedata.category(ch)[0] != "C" else "_" for ch in s)
    s = _UNSAFE.sub("_", s).strip(" ")
    s = s.lstrip(".").strip(" ")
    if not s or set(s) <= {"_", "."}:
        s = default
    if s.split(".")[0].lower() in _RESERVED:
        s = "_" + s
    if len(s.encode("utf-8")) > max_bytes:
        stem, ext = os.path.splitext(s)
        ext = ext if len(ext.encode("utf-8")) <= 16 else ""
        budget = max_bytes - len(ext.encode("utf-8"))
        stem = stem.encode("utf-8")[:budget].decode("utf-8", errors="ignore")
        s = stem + ext
    return s


def atomic_path(path: str, write_fn, *, makedirs: bool = True) -> None:
    """Call ``write_fn(tmp_path)`` to write a temporary file beside ``path``, then move it into place.

    The file is flushed to disk before the rename and gets the permissions of a new file of the
    user (:func:`new_file_mode`).  ``makedirs`` creates missing parent directories (commands check
    their outputs first with :func:`check_output_path`, which requires the parent to exist).
    On any error the temporary file is removed and ``path`` is left as it was.
    """
    d = os.path.dirname(os.path.abspath(path)) or "."
    if makedirs:
        os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=".tmp-", suffix=os.path.splitext(path)[1][:16])
    os.close(fd)
    try:
        write_fn(tmp)
        with open(tmp, "rb") as fh:
            try:
                os.fsync(fh.fileno())
            except OSError as exc:  # some file systems (pipes, certain FUSE mounts) cannot fsync
                if exc.errno not in (errno.EINVAL, errno.ENOTSUP):
                    raise
        os.chmod(tmp, new_file_mode())
        os.replace(tmp, path)
    except BaseException:
        if os.path.lexists(tmp):
            os.unlink(tmp)
        raise


def atomic_write(path: str, write_fn, mode: str = "w", *, makedirs: bool = True) -> None:
    """Write ``path`` atomically through a file handle: ``write_fn(fh)`` (text mode is UTF-8)."""

    def _w(tmp):
        if "b" in mode:
            with open(tmp, mode) as fh:
                write_fn(fh)
        else:
            with open(tmp, mode, encoding="utf-8", newline="") as fh:
                write_fn(fh)

    atomic_path(path, _w, makedirs=makedirs)


def read_text(path: str, limit: int) -> str:
    """Read ``path`` as UTF-8 text (a BOM is dropped), refusing a file of more than ``limit`` bytes.

    Larger -> :class:`InputError` ``"PATH: larger than LIMIT bytes"`` (never a silently cut file);
    not UTF-8 -> :class:`InputError` ``"PATH: not UTF-8 text"``.
    """
    with open(path, "rb") as fh:
        data = fh.read(limit + 1)
    if len(data) > limit:
        raise InputError(f"{path}: larger than {limit:,} bytes")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
