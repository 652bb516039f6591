"""Sensor error models from datasheets, applied to ideal rates or increments.

One :class:`TriadModel` per sensor triad (gyro, accel); every term optional (0/None = absent):

=====================  ==================================================================
noise_density          white noise, N (rad/s/√Hz or m/s²/√Hz); Allan σ(τ) = N/√τ
bias                   turn-on bias, 1σ per axis, drawn once per run
bias_instability       Allan-deviation floor B; Gauss–Markov with ``bias_correlation_time``,
                       else flicker (1/f) from a bank of Gauss–Markov processes (0.3–3000 s)
random_walk            rate/acceleration random walk K; Allan σ(τ) = K √(τ/3)
scale_factor           1σ per axis, drawn once per run
misalignment           1σ cross-axis coupling (rad), drawn once per run (6 off-diagonal terms)
g_sensitivity          gyro only: ω += G f_b, G 1σ per axis-pair, drawn once per run
range                  saturation (clipped, flagged)
resolution             quantisation step (rate units); increments carry the residual
bandwidth              2nd-order Butterworth low-pass at the internal rate
internal_rate          the sensor samples and filters internally at this rate, then decimates
=====================  ==================================================================

Randomness: each run draws from its own stream ``SeedSequence(seed).spawn(runs)[r]``, so a run
is reproducible bit for bit whatever the chunking, and runs are independent.

May import: ``imunav.core``, ``imunav.sensors.allan``, ``imunav.sensors.presets``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from imunav.core.rotations import FloatArray
from imunav.core.units import SPEC, parse
from imunav.core.validation import ImunavError, check_positive, read_toml
from imunav.sensors.allan import gauss_markov_allan_variance

TERMS = ("noise_density", "bias", "bias_instability", "random_walk", "scale_factor",
         "misalignment", "g_sensitivity", "range", "resolution", "bandwidth")


@dataclass(frozen=True)
class TriadModel:
    """Error parameters of one triad, in SI (see the module docstring)."""

    noise_density: float = 0.0
    bias: float = 0.0
    bias_instability: float = 0.0
    bias_correlation_time: float | None = None
    random_walk: float = 0.0
    scale_factor: float = 0.0
    misalignment: float = 0.0
    g_sensitivity: float = 0.0
    range: float | None = None
    resolution: float | None = None
    bandwidth: float | None = None
    internal_rate: float | None = None

    @classmethod
    def from_dict(cls, d: dict, triad: str) -> TriadModel:
        """Parse ``{"noise_density": "0.014 deg/s/sqrt(Hz)", …}`` (numbers are SI)."""
        if not isinstance(d, dict):
            raise ImunavError(f"[{triad}] must be a table")
        allowed = set(SPEC[triad])
        bad = sorted(set(d) - allowed)
        if bad:
            raise ImunavError(f"unknown key(s) in [{triad}]: {', '.join(bad)}; expected "
                              f"{', '.join(sorted(allowed))}")
        return cls(**{k: parse(v, f"{triad}.{k}") for k, v in d.items()})

    def active(self) -> list[str]:
        """The error terms present."""
        return [t for t in TERMS if getattr(self, t, None) not in (None, 0.0)]

    def only(self, term: str | None) -> TriadModel:
        """A copy keeping only ``term`` (and its correlation time); None → ideal."""
        keep = {"bias_correlation_time", "internal_rate"} | ({term} if term else set())
        return replace(self, **{f.name: (getattr(self, f.name) if f.name in keep else f.default)
                                for f in fields(self)})


@dataclass(frozen=True)
class ImuModel:
    """A 6-axis IMU: gyro and accelerometer triads."""

    gyro: TriadModel = field(default_factory=TriadModel)
    accel: TriadModel = field(default_factory=TriadModel)
    name: str = "custom"

    @classmethod
    def from_dict(cls, d: dict, name: str = "custom") -> ImuModel:
        bad = sorted(set(d) - {"gyro", "accel", "name"})
        if bad:
            raise ImunavError(f"unknown table(s) in IMU file: {', '.join(bad)}; expected "
                              "[gyro] and [accel]")
        return cls(TriadModel.from_dict(d.get("gyro", {}), "gyro"),
                   TriadModel.from_dict(d.get("accel", {}), "accel"), d.get("name", name))

    @classmethod
    def from_toml(cls, path: str | Path) -> ImuModel:
        path = Path(path)
        d = read_toml(path, "IMU file")
        return cls.from_dict(d, path.stem)

    @classmethod
    def load(cls, spec: str) -> ImuModel:
        """A preset name or a path to ``IMU.toml``."""
        from imunav.sensors.presets import PRESETS

        if spec in PRESETS:
            return cls.from_dict(PRESETS[spec], spec)
        if spec.endswith(".toml") or Path(spec).is_file():
            return cls.from_toml(spec)
        raise ImunavError(f"--imu {spec!r} is neither a preset ({', '.join(PRESETS)}) nor a "
                          "TOML file")

    def terms(self) -> list[str]:
        """Active terms as ``gyro.noise_density`` etc."""
        return [f"gyro.{t}" for t in self.gyro.active()] + \
               [f"accel.{t}" for t in self.accel.active()]

    def only(self, term: str | None) -> ImuModel:
        """Keep one term (``"gyro.bias"``) — for error budgets; None → ideal."""
        tri, _, name = (term or "").partition(".")
        return ImuModel(self.gyro.only(name if tri == "gyro" else None),
                        self.accel.only(name if tri == "accel" else None), f"{self.name}:{term}")

    @property
    def internal_rate(self) -> float | None:
        r = [x for x in (self.gyro.internal_rate, self.accel.internal_rate) if x]
        return max(r) if r else None

    def decimation(self, rate: float) -> int:
        """How many internal samples make one output sample at ``rate`` Hz:
        ``round(internal_rate / rate)``, at least 1 (1 without an internal rate)."""
        rate = check_positive(rate, "rate")
        return max(1, int(round((self.internal_rate or rate) / rate)))


# ---------------------------------------------------------------------------- processes


def _flicker_bank(T: float | None) -> list[float]:
    return [T] if T else list(np.logspace(np.log10(0.3), np.log10(3000.0), 9))


def bias_instability_sigma(B: float, T: float | None) -> float:
    """Std of each Gauss–Markov component so the Allan-deviation maximum equals ``B``."""
    taus = np.logspace(-3, 5, 4000)
    var = sum(gauss_markov_allan_variance(taus, 1.0, t) for t in _flicker_bank(T))
    return B / float(np.sqrt(var.max()))


class TriadStream:
    """One run of one triad's errors, applied to ideal samples fed in consecutive chunks.

    The constant terms (turn-on bias, scale factor and misalignment matrix, g-sensitivity) are
    drawn from ``rng`` when the stream is created; every time-varying sequence (each
    Gauss–Markov component, the random walk, the white noise) then draws from its own child
    generator, and the filters carry their state, so the output of a run does not depend on
    how it is chunked. Chunk lengths must be multiples of ``decimate`` (but the last).

    ``kind`` is ``rates`` (samples in rate units) or ``increments`` (integrals over each
    ``1/rate`` interval); the output is at ``rate/decimate``.
    """

    def __init__(self, m: TriadModel, kind: str, rate: float, rng: np.random.Generator,
                 decimate: int = 1):
        self.m, self.kind, self.k = m, kind, int(decimate)
        self.rate = check_positive(rate, "rate")
        self.dt = 1.0 / self.rate
        self.bias = rng.normal(0.0, m.bias, 3) if m.bias else np.zeros(3)
        M = np.eye(3)
        if m.scale_factor:
            M = M + np.diag(rng.normal(0.0, m.scale_factor, 3))
        if m.misalignment:
            off = rng.normal(0.0, m.misalignment, (3, 3))
            np.fill_diagonal(off, 0.0)
            M = M + off
        self.matrix = M
        self.g_sens = rng.normal(0.0, m.g_sensitivity, (3, 3)) if m.g_sensitivity else None
        self.gm = []                          # [rng, a, innovation σ, previous value]
        if m.bias_instability:
            sd = bias_instability_sigma(m.bias_instability, m.bias_correlation_time)
            for T in _flicker_bank(m.bias_correlation_time):
                child = rng.spawn(1)[0]
                a = float(np.exp(-self.dt / T))
                # the value before the first sample is drawn from the stationary distribution
                self.gm.append([child, a, sd * np.sqrt(1 - a * a), child.normal(0.0, sd, 3)])
        self.rw_rng = rng.spawn(1)[0] if m.random_walk else None
        self.rw = np.zeros(3)
        self.noise_rng = rng.spawn(1)[0] if m.noise_density else None
        self.sos = None
        if m.bandwidth and m.bandwidth < 0.5 * self.rate:
            from scipy.signal import butter

            self.sos = butter(2, m.bandwidth, fs=self.rate, output="sos")
            self.zi = None            # set from the first sample: the sensor ran before t0
        self.total = np.zeros(3)              # increments: exact running sum (quantisation)
        self.qtotal = np.zeros(3)             # increments: quantised running sum

    def _drift(self, n: int) -> FloatArray:
        from scipy.signal import lfilter

        drift = np.zeros((n, 3))
        for st in self.gm:
            child, a, sw, prev = st
            w = child.normal(0.0, sw, (n, 3))
            y, _ = lfilter([1.0], [1.0, -a], w, axis=0, zi=(a * prev)[None])
            drift += y
            st[3] = y[-1]
        if self.rw_rng is not None:
            walk = np.cumsum(self.rw_rng.normal(0.0, self.m.random_walk * np.sqrt(self.dt),
                                                (n, 3)), axis=0) + self.rw
            self.rw = walk[-1]
            drift += walk
        return drift

    def process(self, ideal: FloatArray, other: FloatArray | None = None
                ) -> tuple[FloatArray, np.ndarray]:
        """Ideal samples (n, 3) → measured samples (n/decimate, 3) and the saturation flag of
        each output sample. ``other``: the ideal accelerometer chunk (gyro g-sensitivity)."""
        m, k, dt = self.m, self.k, self.dt
        n = ideal.shape[0]
        x = ideal / dt if self.kind == "increments" else ideal          # rate units
        # in place, in the order of y = x Mᵀ + bias + drift + G f + noise (the same roundings);
        # a run without drift terms adds no zeros (y + 0 is y: no −0 survives "+ bias")
        y = x @ self.matrix.T
        y += self.bias
        if self.gm or self.rw_rng is not None:
            y += self._drift(n)
        if self.g_sens is not None and other is not None:
            f = other / dt if self.kind == "increments" else other
            y += f @ self.g_sens.T
        if self.noise_rng is not None:
            y += self.noise_rng.normal(0.0, m.noise_density * np.sqrt(self.rate), (n, 3))
        if self.sos is not None:
            from scipy.signal import sosfilt, sosfilt_zi

            if self.zi is None:       # steady state for the first input (no start-up transient)
                self.zi = sosfilt_zi(self.sos)[:, :, None] * y[0]
            y, self.zi = sosfilt(self.sos, y, axis=0, zi=self.zi)
        if m.range:
            over = np.abs(y) > m.range
            flags = over[:, 0] | over[:, 1] | over[:, 2]          # any axis (8× np.any's speed)
            np.clip(y, -m.range, m.range, out=y)
        else:
            flags = np.zeros(n, dtype=bool)
        if k > 1:
            nn = n // k
            if self.kind == "increments":
                y = y[: nn * k].reshape(nn, k, 3).mean(axis=1)     # Σ increments / (k·dt)
                flags = flags[: nn * k].reshape(nn, k).any(axis=1)
            else:
                y, flags = y[::k], flags[::k]                      # the output instants
        if self.kind == "increments":
            y *= dt * k
            if m.resolution:
                q = m.resolution * dt * k
                total = np.cumsum(y, axis=0)                       # residual carry: no loss
                total += self.total
                qt = total / q
                np.round(qt, out=qt)
                qt *= q
                y = np.empty_like(qt)                              # np.diff(qt, prepend=…)
                np.subtract(qt[:1], self.qtotal, out=y[:1])
                np.subtract(qt[1:], qt[:-1], out=y[1:])
                self.total, self.qtotal = total[-1], qt[-1]
        elif m.resolution:
            y = np.round(y / m.resolution) * m.resolution
        return y, flags


def apply_triad(m: TriadModel, ideal: FloatArray, kind: str, rate: float, rng,
                other: FloatArray | None = None, decimate: int = 1
                ) -> tuple[FloatArray, np.ndarray]:
    """One run of one triad on a whole signal: ideal (n, 3) at ``rate`` → measured signal at
    ``rate/decimate`` and the saturation flags per output sample (a :class:`TriadStream` fed
    once). ``other`` is the ideal accelerometer signal (same kind) for the gyro's
    g-sensitivity."""
    return TriadStream(m, kind, rate, rng, decimate).process(ideal, other)


class MeasureStream:
    """One run of a 6-axis IMU: ideal gyro and accel chunks → measured chunks and flags."""

    def __init__(self, model: ImuModel, kind: str, rate: float, rng: np.random.Generator,
                 decimate: int = 1):
        g2 = np.random.default_rng(rng.integers(2**63))
        self.gyro = TriadStream(model.gyro, kind, rate, g2, decimate)
        self.accel = TriadStream(model.accel, kind, rate, rng, decimate)

    def process(self, gyro: FloatArray, accel: FloatArray
                ) -> tuple[FloatArray, FloatArray, np.ndarray]:
        gm, fg = self.gyro.process(gyro, other=accel)
        am, fa = self.accel.process(accel)
        return gm, am, fg | fa


def measure(model: ImuModel, gyro: FloatArray, accel: FloatArray, kind: str, rate: float,
            rng, decimate: int = 1) -> tuple[FloatArray, FloatArray, np.ndarray]:
    """One run: ideal gyro and accel (n, 3) → measured (gyro, accel, saturation flags)."""
    return MeasureStream(model, kind, rate, rng, decimate).process(gyro, accel)
