"""SQL of the launcher database's schema versions (:data:`MIGRATIONS`); the layout is described in
:mod:`tennislab.launcher.db` and docs/database.md."""

_V1 = """
CREATE TABLE machine (
    id INTEGER PRIMARY KEY CHECK (id = 1),
    hash TEXT NOT NULL,
    spec_json TEXT NOT NULL,
    position_x REAL NOT NULL,
    position_y REAL NOT NULL,
    physics_json TEXT NOT NULL,
    config_json TEXT NOT NULL,
    tennislab_version TEXT NOT NULL,
    created_utc TEXT NOT NULL
);
CREATE TABLE hits (
    id INTEGER PRIMARY KEY,
    height_m REAL NOT NULL, speed_kmh REAL NOT NULL, elevation_deg REAL NOT NULL,
    heading_deg REAL NOT NULL, spin_rpm REAL NOT NULL, spin_axis_deg REAL NOT NULL,
    land_x REAL NOT NULL, land_y REAL NOT NULL, net_clearance_m REAL NOT NULL,
    flight_time_s REAL NOT NULL, bounce_speed_ms REAL NOT NULL, bounce_spin_rpm REAL NOT NULL,
    apex_z_m REAL NOT NULL
);
CREATE VIRTUAL TABLE hits_rtree USING rtree(id, min_x, max_x, min_y, max_y,
                                            min_speed, max_speed, min_spin, max_spin);
CREATE TABLE fills (
    id INTEGER PRIMARY KEY,
    grid_hash TEXT NOT NULL UNIQUE,
    grid_json TEXT NOT NULL,
    n_rows INTEGER NOT NULL,
    chunk_size INTEGER NOT NULL,
    n_chunks INTEGER NOT NULL,
    started_utc TEXT NOT NULL,
    finished_utc TEXT
);
CREATE TABLE fill_chunks (
    fill_id INTEGER NOT NULL REFERENCES fills(id),
    chunk INTEGER NOT NULL,
    n_hits INTEGER NOT NULL,
    PRIMARY KEY (fill_id, chunk)
) WITHOUT ROWID;
"""

_V2 = """
CREATE TABLE drills (
    id INTEGER PRIMARY KEY,
    name TEXT NOT NULL UNIQUE,
    filename TEXT NOT NULL,
    format_version TEXT,
    revision INTEGER NOT NULL,
    sha256 TEXT NOT NULL,
    source BLOB NOT NULL,
    sequence_json TEXT,
    imported_utc TEXT NOT NULL
);
CREATE TABLE drill_shots (
    drill_id INTEGER NOT NULL REFERENCES drills(id) ON DELETE CASCADE,
    idx INTEGER NOT NULL,
    shot_json TEXT NOT NULL,
    PRIMARY KEY (drill_id, idx)
) WITHOUT ROWID;
"""

# v3: a 2-D R*Tree for lookups with neither speed nor spin given.  In the 4-D tree the
# speed and spin dimensions keep the landing "sheets" of different speeds apart, so a box
# query over every speed visits one subtree per sheet (~30 ms at 10^6 hits); the 2-D tree
# packs nearby landings of all sheets into the same leaves.  Existing hits are indexed.
_V3 = """
CREATE VIRTUAL TABLE hits_xy USING rtree(id, min_x, max_x, min_y, max_y);
INSERT INTO hits_xy SELECT id, land_x, land_x, land_y, land_y FROM hits;
"""

# v4: covering B-tree indexes for lookups that fix at most one of speed and spin, replacing hits_xy.
# With an open speed or spin range the 4-D tree's leaves (which mix speeds and spins) reach the
# target by the hundred: 10-100 ms at 10^7 hits.  Landings lie on dense rays (one per heading
# step); hits_xy's square boxes read 10^4 entries of the nearest ray at 10^7 hits, and its leaves
# on the ray of heading 0 (y constant: zero area, no guide for the R*Tree's insertion) span metres.
# An index ordered by 1 cm bands of y, then x reads one range per band, clipped to a disc.
_V4 = """
DROP TABLE hits_xy;
CREATE INDEX hits_cell ON hits (CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y, net_clearance_m,
                                height_m, spin_axis_deg);
CREATE INDEX hits_speed_cell ON hits (speed_kmh, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y,
                                      net_clearance_m);
CREATE INDEX hits_spin_cell ON hits (spin_rpm, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y,
                                     net_clearance_m);
"""

# v5: the trajectory branch of every hit (low/high) and band indexes keyed by it (after the speed or spin) that
# carry what the trajectory
# preferences filter on (branch, apex, flight time; speed and spin in each other's index for tolerance
# windows; height and spin axis).  Stored hits get their branch from their neighbours in elevation
# (:func:`_branch_from_neighbours`, run by :func:`migrate`); new fills fly it (table.fly_chunk).
_V5 = """
ALTER TABLE hits ADD COLUMN branch INTEGER NOT NULL DEFAULT 0;
DROP INDEX hits_cell;
DROP INDEX hits_speed_cell;
DROP INDEX hits_spin_cell;
CREATE INDEX hits_cell ON hits (branch, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y,
                                net_clearance_m, apex_z_m, flight_time_s, height_m, spin_axis_deg, speed_kmh, spin_rpm);
CREATE INDEX hits_speed_cell ON hits (speed_kmh, branch, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x,
                                      land_y, net_clearance_m, apex_z_m, flight_time_s, spin_rpm, height_m,
                                      spin_axis_deg);
CREATE INDEX hits_spin_cell ON hits (spin_rpm, branch, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x,
                                     land_y, net_clearance_m, apex_z_m, flight_time_s, speed_kmh, height_m,
                                     spin_axis_deg);
"""

#: version -> SQL script that upgrades a file from ``version - 1`` to ``version``.
MIGRATIONS = {1: _V1, 2: _V2, 3: _V3, 4: _V4, 5: _V5}
