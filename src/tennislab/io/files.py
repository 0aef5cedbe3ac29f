"""Files that tennislab reads and writes: inputs opened one way, outputs checked before the work and
written atomically.

Inputs (every reader of :mod:`tennislab.io`, the batch manifest, the launcher database):

* :func:`read_input` / :func:`read_text` - the one input opener: a regular file only (a FIFO, a device
  or a socket is refused in one line without blocking: the path is ``stat``-ed first and opened
  ``O_NONBLOCK``), at most *limit* bytes (refused before reading when the file says it is larger),
  UTF-8 for text.  :func:`check_input_file` is the same check for a file another library opens
  (SQLite).  Errors name the file (escaped: :func:`shown`).

Outputs (every writer):

* :func:`check_output_path` / :func:`check_output_dir` - the one output checker, run *before* any work:
  the parent is an existing, writable directory, not a regular file; the name fits the file system;
  the extension is one the writer supports; an existing output is a regular file (never a FIFO, a
  device, a socket, nor a link to one) and is not one of the command's inputs (:func:`command_files`).
* :func:`safe_basename` - a file name that came from data (a database, a drill file) reduced to a plain
  base name: never a path, never hidden, never too long.
* :func:`atomic_path` / :func:`atomic_write` - write to a temporary name in the destination directory,
  flush it to disk, give it the permissions a new file of the user gets (``0666 & ~umask``, typically
  0644; a plain temporary file would be owner-only, 0600) and rename it into place (``os.replace`` is
  atomic on POSIX and Windows): nothing half-written on error or interruption, no folder left that it
  created, and an OS error (no space left, ...) names the file.

Within :func:`command_files` (the CLI runs every command in one), each input read is remembered by its
identity (device, inode), and an output that is one of them is refused: a command never overwrites
what it reads.  File names may be in any encoding (bytes that are not UTF-8 are shown as ``\\xff``).

Errors are :class:`~tennislab.errors.InputError` whose message starts with the parameter's name
(``plot: ...``) or the file's; the CLI turns a parameter into the flag (``--plot: ...``).
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import re
import stat
import tempfile
import unicodedata

from tennislab.errors import InputError, escape_text

#: longest file-name component accepted when the file system does not say [bytes] (ext4, APFS, NTFS)
NAME_MAX = 255


def shown(path) -> str:
    """A file name as messages show it: any encoding, one line (:func:`tennislab.errors.escape_text`)."""
    p = os.fspath(path) if isinstance(path, str | bytes | os.PathLike) else str(path)
    return escape_text(os.fsdecode(p) if isinstance(p, bytes) else p)


def is_utf8_name(path) -> bool:
    """Whether the name ``path`` is UTF-8 text (a name from the command line may hold any bytes: they
    arrive as lone surrogates), so that a text file, a database or a TOML configuration can hold it."""
    try:
        (os.fsdecode(path) if isinstance(path, bytes) else os.fspath(path)).encode("utf-8")
    except (UnicodeError, TypeError):
        return False
    return True


# ------------------------------------------------------------------ the command's files
_INPUTS: contextvars.ContextVar[dict | None] = contextvars.ContextVar("tennislab_inputs", default=None)


@contextlib.contextmanager
def command_files():
    """The files of one command: inputs read inside are remembered, and an output that is one of them
    is refused (by :func:`check_output_path` and :func:`atomic_path`).  Nested scopes share the outer one."""
    if _INPUTS.get() is not None:
        yield
        return
    token = _INPUTS.set({})
    try:
        yield
    finally:
        _INPUTS.reset(token)


def note_input(path, st: os.stat_result | None = None) -> None:
    """Remember ``path`` (by device and inode) as an input of the current command (:func:`command_files`)."""
    seen = _INPUTS.get()
    if seen is None:
        return
    if st is None:
        try:
            st = os.stat(path)
        except OSError:
            return
    seen[(st.st_dev, st.st_ino)] = shown(path)


def _as_input(path) -> str | None:
    """The name under which ``path`` (an existing file) was read by the current command, else None."""
    seen = _INPUTS.get()
    if not seen:
        return None
    try:
        st = os.stat(path)
    except OSError:
        return None
    return seen.get((st.st_dev, st.st_ino))


def check_not_input(param: str, path) -> None:
    """Refuse an output ``path`` that is an input of the current command (the same file, by identity)."""
    name = _as_input(path)
    if name is not None:
        what = "" if name == shown(path) else f" (the same file as {name})"
        raise InputError(
            f"{param}: {shown(path)} is also an input of this command{what}; refusing to overwrite it - "
            "write the output to another file"
        )


def same_file(a, b) -> bool:
    """Whether two paths name one existing file (device and inode)."""
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):
        return False


# ------------------------------------------------------------------ inputs
_KINDS = (
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISDIR, "a directory"),
)


def file_kind(mode: int) -> str:
    """What a file of this ``st_mode`` is, for a message (``a FIFO (named pipe)``, ``a directory``, ...)."""
    for test, kind in _KINDS:
        if test(mode):
            return kind
    return "a regular file" if stat.S_ISREG(mode) else "a special file"


def _os_error(name: str, exc: OSError) -> InputError:
    return InputError(f"{shown(name)}: {'no such file' if exc.errno == errno.ENOENT else exc.strerror or exc}")


def check_input_file(path, *, what: str = "file") -> os.stat_result:
    """``os.stat`` of an input that must be an existing regular file (following links), else one line:
    ``PATH: no such file``, ``PATH: is a directory, expected a file``, ``PATH: is a FIFO (named pipe),
    not a regular file``.  Nothing is opened, so a FIFO never blocks."""
    try:
        st = os.stat(path)
    except (OSError, ValueError) as exc:
        if isinstance(exc, ValueError):  # an embedded NUL
            raise InputError(f"{shown(path)}: not a valid file name") from None
        raise _os_error(path, exc) from None
    if stat.S_ISDIR(st.st_mode):
        raise InputError(f"{shown(path)}: is a directory, expected a {what}")
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"{shown(path)}: is {file_kind(st.st_mode)}, not a regular file")
    return st


def _too_big(path, limit: int, what: str | None) -> InputError:
    if what:
        return InputError(f"{shown(path)}: larger than a {what} may be ({limit} bytes)")
    return InputError(f"{shown(path)}: larger than {limit:,} bytes")


def read_input(path, limit: int, *, what: str | None = None) -> bytes:
    """The bytes of the input file ``path`` (the one input opener of every reader).

    A regular file only: checked with :func:`check_input_file` before it is opened, opened with
    ``O_NONBLOCK`` (a FIFO swapped in meanwhile cannot block) and checked again on the open file.
    A file larger than ``limit`` bytes is refused (from its size before reading, and by reading at most
    ``limit + 1`` bytes): ``PATH: larger than LIMIT bytes`` (``what``: ``larger than a WHAT may be``),
    never silently cut.  The file is remembered as an input of the current command
    (:func:`command_files`).  OS errors are one :class:`InputError` naming the file.
    """
    st = check_input_file(path)
    if st.st_size > limit:
        raise _too_big(path, limit, what)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        raise _os_error(path, exc) from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{shown(path)}: is {file_kind(st.st_mode)}, not a regular file")
        chunks, n = [], 0
        while n <= limit:
            b = os.read(fd, min(1 << 20, limit + 1 - n))
            if not b:
                break
            chunks.append(b)
            n += len(b)
    except OSError as exc:
        raise _os_error(path, exc) from None
    finally:
        os.close(fd)
    if n > limit:
        raise _too_big(path, limit, what)
    note_input(path, st)
    return b"".join(chunks)


def decode_text(data: bytes, name: str, *, nul: bool = True) -> str:
    """UTF-8 text of a file's bytes (a BOM is dropped): ``NAME: not UTF-8 text (byte N)`` otherwise;
    with ``nul=False`` a NUL character is refused too (``NAME: contains NUL bytes``)."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{shown(name)}: not UTF-8 text (byte {exc.start})") from None
    if not nul and "\x00" in text:
        raise InputError(f"{shown(name)}: binary data (NUL bytes), not a text file")
    return text


def read_text(path, limit: int, *, what: str | None = None, nul: bool = True) -> str:
    """Read ``path`` as UTF-8 text (:func:`read_input`, then :func:`decode_text`)."""
    return decode_text(read_input(path, limit, what=what), path, nul=nul)


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


def _check_directory(param: str, label: str, directory: str, *, create: bool) -> None:
    """The directory that will hold an output exists (or, with ``create``, can be made) and is writable."""
    existing = _nearest_existing(directory)
    if os.path.exists(existing) and not os.path.isdir(existing):
        raise InputError(f"{param}: {label}: {shown(existing)} is a file, not a directory")
    if existing != directory and not create:
        raise InputError(f"{param}: {label}: directory {shown(directory)} does not exist")
    if not os.path.isdir(existing):  # a dangling symlink
        raise InputError(f"{param}: {label}: {shown(existing)} is not a directory")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise InputError(f"{param}: {label}: directory {shown(existing)} is not writable")
    limit = _name_max(existing)
    rest = os.path.relpath(directory, existing) if existing != directory else ""
    for part in rest.split(os.sep) if rest else ():
        if len(os.fsencode(part)) > limit:
            raise InputError(f"{param}: {label}: a directory name is {len(part)} characters long (limit {limit} bytes)")


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
        raise InputError(f"{param}: {shown(p)} is a directory, expected a file name")
    full = os.path.abspath(p)
    directory, name = os.path.split(full)
    _check_directory(param, shown(p), directory, create=create_dirs)
    limit = _name_max(_nearest_existing(directory))
    if len(os.fsencode(name)) > limit:
        raise InputError(f"{param}: the file name is {len(name)} characters long (limit {limit} bytes)")
    if suffixes is not None:
        allowed = tuple(s.lower() for s in suffixes)
        ext = os.path.splitext(name)[1].lower()
        if ext not in allowed:
            got = f"'{ext}'" if ext else "no extension"
            raise InputError(
                f"{param}: {shown(p)}: unsupported file type ({shown(got)}); allowed: {', '.join(allowed)}"
            )
    check_existing_output(param, full, p)
    return p


_STREAMS = re.compile(r"^/(proc/|dev/(fd/|std(in|out|err)$|tty|pts/))")


def stream_link(path) -> str | None:
    """The first target of the chain of links at ``path`` that names a stream rather than a file
    (``/dev/stdout``, ``/dev/fd/1``, ``/proc/self/fd/1``, a terminal), else None.  Such a link points
    at whatever that descriptor is at the moment (a pipe, a terminal, another program's file)."""
    p = os.path.abspath(os.fspath(path))
    for _ in range(40):  # the kernel's own limit on a chain of links
        try:
            target = os.readlink(p)
        except OSError:
            return None
        p = os.path.normpath(os.path.join(os.path.dirname(p), target))
        if _STREAMS.match(p if isinstance(p, str) else os.fsdecode(p)):
            return p
    return None


def check_existing_output(param: str, path, shown_as=None) -> None:
    """An output that exists already must be a regular file (itself, or the file a link names) that
    is writable and not an input of this command: a FIFO, a device, a socket or a link to one (such
    as ``/dev/stdout``) is refused - replacing it would destroy it or write where nobody looks."""
    name = shown(path if shown_as is None else shown_as)
    try:
        lst = os.lstat(path)
    except OSError:
        return  # a new file
    try:
        st = os.stat(path)
    except OSError:
        st = lst  # a dangling link: replaced by the new file
    link = stat.S_ISLNK(lst.st_mode)
    stream = stream_link(path) if link else None
    if stream is not None:
        raise InputError(
            f"{param}: {name} is a link to {shown(stream)} (a device or a process's stream), not a file; "
            "refusing to replace it"
        )
    if not stat.S_ISREG(st.st_mode) and not stat.S_ISLNK(st.st_mode):
        target = f" (a link to {shown(os.path.realpath(path))})" if link else ""
        raise InputError(
            f"{param}: {name}{target} is {file_kind(st.st_mode)}, not a regular file; refusing to replace it"
        )
    if not link and not os.access(path, os.W_OK):
        raise InputError(f"{param}: {name}: the existing file is not writable")
    check_not_input(param, path)


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
        raise InputError(f"{param}: {shown(p)} is a file, expected a directory")
    _check_directory(param, shown(p), full, create=create)
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


def _missing_dirs(d: str) -> list[str]:
    """The directories of ``d`` that do not exist yet, deepest first."""
    out = []
    while not os.path.lexists(d):
        out.append(d)
        parent = os.path.dirname(d)
        if parent == d:
            break
        d = parent
    return out


def atomic_path(path: str, write_fn, *, makedirs: bool = True) -> None:
    """Call ``write_fn(tmp_path)`` to write a temporary file beside ``path``, then move it into place.

    The file is flushed to disk before the rename and gets the permissions of a new file of the
    user (:func:`new_file_mode`).  ``makedirs`` creates missing parent directories (commands check
    their outputs first with :func:`check_output_path`, which requires the parent to exist).
    An existing ``path`` must be a regular file that is not an input of the command
    (:func:`check_existing_output`).  On any error the temporary file and the directories made
    here are removed, ``path`` is left as it was, and an ``OSError`` names ``path``
    (``PATH: No space left on device``).
    """
    check_existing_output("output", path)
    d = os.path.dirname(os.path.abspath(path)) or "."
    made = _missing_dirs(d) if makedirs else []
    tmp = None
    try:
        if made:
            os.makedirs(d, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=d, prefix=".tmp-", suffix=os.path.splitext(path)[1][:16])
        os.close(fd)
        write_fn(tmp)
        with open(tmp, "rb") as fh:
            try:
                os.fsync(fh.fileno())
            except OSError as exc:  # some file systems (pipes, certain FUSE mounts) cannot fsync
                if exc.errno not in (errno.EINVAL, errno.ENOTSUP):
                    raise
        os.chmod(tmp, new_file_mode())
        check_existing_output("output", path)  # nothing replaced it with a FIFO or an input meanwhile
        os.replace(tmp, path)
        tmp = None
    except BaseException as exc:
        if tmp is not None and os.path.lexists(tmp):
            os.unlink(tmp)
        for m in made:  # deepest first; a folder someone else filled meanwhile stays
            try:
                os.rmdir(m)
            except OSError:
                break
        if isinstance(exc, OSError) and not isinstance(exc, InputError):
            raise InputError(f"{shown(path)}: cannot be written ({exc.strerror or type(exc).__name__})") from None
        if isinstance(exc, UnicodeEncodeError):  # text that is no UTF-8 (a name in another encoding)
            raise InputError(
                f"{shown(path)}: cannot be written (it would hold {shown(exc.object[exc.start : exc.end])}, "
                "which is not UTF-8 text)"
            ) from None
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
