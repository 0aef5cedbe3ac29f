"""Reading and writing files (CSV, JSON, YAML, TOML, Parquet): the leaves of the package.

Readers parse bytes into plain data (dicts, arrays, small dataclasses of io's own) and check the
file's form (size, encoding, depth, columns); a malformed file is an :class:`~tennislab.errors.InputError`
naming the file and the field.  The domain packages give the data its meaning.  Outputs are written
atomically (:func:`atomic_write`) to paths checked before any work (:func:`check_output_path`,
:func:`check_output_dir`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.io.aero_table import read_aero_table
    from tennislab.io.cameras import parse_cameras, parse_detections, read_cameras, read_detections
    from tennislab.io.config import read_config, read_player_file
    from tennislab.io.courtvision import read_ball_trajectory, read_pbp, read_serves
    from tennislab.io.drill import load_drill_data, write_csv
    from tennislab.io.files import (
        atomic_write,
        check_input_file,
        check_output_dir,
        check_output_path,
        command_files,
        is_utf8_name,
        read_text,
        same_file,
        shown,
    )
    from tennislab.io.formats import check_unicode, unique_pairs
    from tennislab.io.hawkeye import parse_points, read_points
    from tennislab.io.material_csv import read_friction_angles, read_load_deformation
    from tennislab.io.surface_file import is_surface_file, read_surface
    from tennislab.io.track import Track, parse_track, read_track, track_to_csv

__all__ = [
    "Track",
    "atomic_write",
    "check_input_file",
    "command_files",
    "check_unicode",
    "is_utf8_name",
    "same_file",
    "shown",
    "unique_pairs",
    "check_output_dir",
    "check_output_path",
    "is_surface_file",
    "load_drill_data",
    "parse_cameras",
    "parse_detections",
    "parse_points",
    "parse_track",
    "read_aero_table",
    "read_ball_trajectory",
    "read_cameras",
    "read_config",
    "read_detections",
    "read_friction_angles",
    "read_load_deformation",
    "read_pbp",
    "read_player_file",
    "read_points",
    "read_serves",
    "read_surface",
    "read_text",
    "read_track",
    "track_to_csv",
    "write_csv",
]
__getattr__, __dir__ = attach_stub(__name__, __file__)
