"""Floor 3 (beside strapdown) — files: motion files (MOTION.toml, pose CSV, waypoints TOML),
the signal/truth/navigation CSVs, result JSON, and readers of real recordings (x-io x-IMU3,
x-IMU, generic CSV). It reads and writes; what is computed from recordings is
:mod:`imunav.analysis.recordings`.

Modules: :mod:`~imunav.io.files`, :mod:`~imunav.io.csvio`, :mod:`~imunav.io.paths`,
:mod:`~imunav.io.realdata`.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``.
"""

from imunav.io.aiding import read_aiding, write_aiding
from imunav.io.files import (
    HEADERS,
    INCREMENTS_HEADER,
    POSE_HEADER,
    RATES_HEADER,
    STATE_HEADER,
    STATE_HEADERS,
    WGS84_STATE_HEADER,
    SignalFile,
    load_motion,
    load_motion_toml,
    load_poses,
    load_waypoints,
    read_initial_state,
    read_signals,
    read_states,
    state_columns,
    write_json,
    write_signals,
    write_states,
)
from imunav.io.realdata import READERS, Recording, read_generic, read_ximu, read_ximu3

__all__ = ["HEADERS", "INCREMENTS_HEADER", "POSE_HEADER", "RATES_HEADER", "READERS", "Recording",
           "STATE_HEADER", "STATE_HEADERS", "SignalFile", "WGS84_STATE_HEADER", "load_motion",
           "load_motion_toml", "load_poses", "load_waypoints", "read_aiding", "read_generic",
           "read_initial_state", "read_signals", "read_states", "read_ximu", "read_ximu3",
           "state_columns", "write_aiding", "write_json", "write_signals", "write_states"]
