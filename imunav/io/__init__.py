"""Floor 3 (beside strapdown) — files: motion files (MOTION.toml, pose CSV, waypoints TOML),
the signal/truth/navigation CSVs, result JSON, and readers of real recordings (x-io x-IMU3,
x-IMU, generic CSV) and of RTKLIB's solution and time-tag files. It reads and writes; what is
computed from recordings is :mod:`imunav.analysis.recordings`.

Modules: :mod:`~imunav.io.files`, :mod:`~imunav.io.csvio`, :mod:`~imunav.io.paths`,
:mod:`~imunav.io.realdata`, :mod:`~imunav.io.rtklib`.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``.
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
from imunav.io.realdata import (
    READERS,
    Recording,
    check_imu_units,
    read_generic,
    read_ximu,
    read_ximu3,
)
from imunav.io.rtklib import PosSolution, TimeTag, imu_times, read_pos, read_tag

__all__ = ["HEADERS", "INCREMENTS_HEADER", "POSE_HEADER", "PosSolution", "RATES_HEADER", "READERS",
           "Recording", "STATE_HEADER", "STATE_HEADERS", "SignalFile", "TimeTag",
           "WGS84_STATE_HEADER", "check_imu_units", "imu_times", "load_motion",
           "load_motion_toml", "load_poses", "load_waypoints", "read_aiding", "read_generic",
           "read_initial_state", "read_pos", "read_signals", "read_states", "read_tag",
           "read_ximu", "read_ximu3", "state_columns", "write_aiding", "write_json",
           "write_signals", "write_states"]
