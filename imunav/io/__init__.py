"""Layer 5 — files: motion files (MOTION.toml, pose CSV, waypoints TOML), the
signal/truth/navigation CSVs, result JSON, and real
recordings (x-io x-IMU3, x-IMU, generic CSV).

Modules: :mod:`~imunav.io.files`, :mod:`~imunav.io.realdata`.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.analysis``.
"""

from imunav.io.files import (
    HEADERS,
    INCREMENTS_HEADER,
    POSE_HEADER,
    RATES_HEADER,
    STATE_HEADER,
    SignalFile,
    load_motion,
    load_motion_toml,
    load_poses,
    load_waypoints,
    read_initial_state,
    read_signals,
    read_states,
    write_json,
    write_signals,
    write_states,
)
from imunav.io.realdata import READERS, Recording, read_generic, read_ximu, read_ximu3

__all__ = ["HEADERS", "INCREMENTS_HEADER", "POSE_HEADER", "RATES_HEADER", "READERS", "Recording",
           "STATE_HEADER", "SignalFile", "load_motion", "load_motion_toml", "load_poses",
           "load_waypoints", "read_generic",
           "read_initial_state", "read_signals", "read_states",
           "read_ximu", "read_ximu3", "write_json", "write_signals", "write_states"]
