"""Drill files (YAML or JSON) read into plain data, with their form checked; no meaning given here.

The launcher's drill format (docs/launcher.md) is interpreted by :mod:`tennislab.launcher.drills`;
this reader only turns bytes into dicts, lists, strings and numbers, and refuses before any
expansion what could exhaust the machine:

* more than :data:`MAX_BYTES` bytes (checked on the file's size, before reading it);
* not UTF-8 text;
* nesting deeper than :data:`MAX_DEPTH`;
* more than :data:`MAX_NODES` values once YAML aliases are expanded (an "alias bomb" of a
  few hundred bytes that would expand to 10^11 values is counted from the parser's events,
  never built).

Every error is one line naming the file (:class:`~tennislab.errors.InputError`).
"""

from __future__ import annotations

import csv

import yaml

from tennislab.errors import InputError
from tennislab.io.files import read_input
from tennislab.io.formats import load_json_document

#: Largest drill file read [bytes] (the shipped drills are ~1-2 kB).
MAX_BYTES = 256 * 1024
#: Deepest nesting of mappings and lists.
MAX_DEPTH = 32
#: Most values (scalars, mappings, lists), YAML aliases expanded.
MAX_NODES = 50_000

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def drill_format(path: str) -> str:
    """``json`` for a ``.json`` file, else ``yaml``."""
    return "json" if str(path).lower().endswith(".json") else "yaml"


def read_drill_bytes(path: str) -> bytes:
    """The bytes of a drill file; InputError if missing, not a regular file, or larger than :data:`MAX_BYTES`."""
    return read_input(path, MAX_BYTES, what="drill file")


def parse_drill_bytes(data: bytes, source: str = "<drill>", fmt: str = "yaml"):
    """Plain data (dicts, lists, str, int, float, bool, None) of a drill file's bytes (module docstring)."""
    if len(data) > MAX_BYTES:
        raise InputError(f"{source}: {len(data)} bytes is larger than a drill file may be ({MAX_BYTES} bytes)")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{source}: not UTF-8 text (byte {exc.start})") from None
    if fmt == "json":
        obj = load_json_document(text, source, max_depth=MAX_DEPTH)
        _check_tree(obj, source)
        return obj
    _check_yaml_events(text, source)
    try:
        return yaml.load(text, Loader=_Loader)  # a safe loader, bounded by the checks above
    except Exception as exc:  # the parser's own errors (and int() of a 5000-digit number): one line
        raise InputError(f"{source}: not valid YAML: {' '.join(str(exc).split())}") from None


def _check_yaml_events(text: str, source: str) -> None:
    """Depth and expanded size of a YAML document from the parser's events (nothing is built)."""
    frames: list[list] = []  # [expanded size so far, anchor, keys seen (a mapping) or None, next is a key]
    anchors: dict[str, int] = {}
    total = 0
    try:
        for ev in yaml.parse(text, Loader=_Loader):
            if frames and isinstance(ev, _NODE_EVENTS) and frames[-1][2] is not None:
                top = frames[-1]
                if top[3]:
                    _check_key(top[2], ev, source)
                top[3] = not top[3]
            if isinstance(ev, (yaml.MappingStartEvent, yaml.SequenceStartEvent)):
                if len(frames) >= MAX_DEPTH:
                    raise InputError(f"{source}: nested deeper than {MAX_DEPTH} levels")
                frames.append([1, ev.anchor, set() if isinstance(ev, yaml.MappingStartEvent) else None, True])
                continue
            if isinstance(ev, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                size, anchor = frames.pop()[:2]
            elif isinstance(ev, yaml.ScalarEvent):
                size, anchor = 1, ev.anchor
            elif isinstance(ev, yaml.AliasEvent):
                if ev.anchor not in anchors:
                    raise InputError(f"{source}: not valid YAML: alias *{ev.anchor} before its anchor")
                size, anchor = anchors[ev.anchor], None
            else:
                continue
            if anchor is not None:
                anchors[anchor] = size
            if frames:
                frames[-1][0] += size
                grown = frames[-1][0]
            else:
                total += size
                grown = total
            if grown > MAX_NODES:
                raise InputError(
                    f"{source}: expands to more than {MAX_NODES} values (YAML aliases included); not a drill file"
                )
    except yaml.YAMLError as exc:
        raise InputError(f"{source}: not valid YAML: {' '.join(str(exc).split())}") from None


_NODE_EVENTS = (yaml.ScalarEvent, yaml.AliasEvent, yaml.MappingStartEvent, yaml.SequenceStartEvent)


def _check_key(keys: set, ev, source: str) -> None:
    """A mapping's key must not repeat (YAML's rule; PyYAML would silently keep the last value)."""
    if isinstance(ev, yaml.ScalarEvent):
        key: object = ("scalar", ev.value)
    elif isinstance(ev, yaml.AliasEvent):
        key = ("alias", ev.anchor)
    else:
        return  # a collection as a key: never equal to another one here
    if key in keys and key != ("scalar", "<<"):
        shown = ev.value if isinstance(ev, yaml.ScalarEvent) else f"*{ev.anchor}"
        line = ev.start_mark.line + 1 if ev.start_mark is not None else "?"
        raise InputError(f"{source}: duplicate key {shown[:40]!r} (line {line}); each key once")
    keys.add(key)


def _check_tree(obj, source: str) -> None:
    """Depth and size of parsed JSON (walked iteratively)."""
    stack = [(obj, 0)]
    n = 0
    while stack:
        v, depth = stack.pop()
        n += 1
        if n > MAX_NODES:
            raise InputError(f"{source}: more than {MAX_NODES} values; not a drill file")
        if isinstance(v, (dict, list)):
            if depth >= MAX_DEPTH:
                raise InputError(f"{source}: nested deeper than {MAX_DEPTH} levels")
            stack.extend((x, depth + 1) for x in (v.values() if isinstance(v, dict) else v))


def load_drill_data(path: str):
    """(plain data, raw bytes, format) of a drill file."""
    data = read_drill_bytes(path)
    fmt = drill_format(path)
    return parse_drill_bytes(data, path, fmt), data, fmt


def write_csv(rows, columns, fh) -> None:
    """Write dict rows with the given columns to a text stream (floats with 6 significant digits)."""
    w = csv.DictWriter(fh, fieldnames=list(columns), lineterminator="\n", extrasaction="ignore")
    w.writeheader()
    for row in rows:
        w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
