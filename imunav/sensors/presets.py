"""IMU presets: every term with its value, its unit and where it comes from.

:data:`PRESET_SPECS` holds each preset as a :class:`Preset`: the part's document, its grade and,
per triad, one :class:`Spec` per error term — the value as an ``IMU.toml`` spells it, its
**basis** (:data:`BASES`: the datasheet's figure; a typical value from a published
characterisation of that part where the datasheet is silent; a setting the user chooses; a
representative specification level) and its **source** (document, revision, table or section,
the datasheet's own words), and whether that number was read against a stored copy of the
source (``checked``). :data:`PRESETS` is the same data as ``IMU.toml`` tables (what
:meth:`~imunav.sensors.models.ImuModel.load` reads), and :func:`preset_table` writes the docs'
page ``docs/presets.md`` from it, so the page cannot drift from the code (a test compares them).

Turn-on bias, scale factor and misalignment are used as 1σ (datasheets give ± typical values).
Where a datasheet gives no figure for a term, the term is absent rather than invented: the
in-run bias instability of consumer parts is taken from a published Allan-variance
characterisation of the part where one was found (basis ``"typical"``), and otherwise left out —
then every answer about the part warns that it has no bias instability
(:meth:`~imunav.sensors.models.ImuModel.missing_term_warnings`). Check the numbers against the
revision of the part you use before relying on them.

May import: nothing from imunav (data only).
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["BASES", "PRESETS", "PRESET_SPECS", "Preset", "Spec", "preset_table"]

#: What a value rests on.
BASES = {
    "datasheet": "the datasheet's typical figure",
    "typical": "a typical value from a published characterisation of the part (the datasheet "
               "is silent)",
    "setting": "a setting the user chooses (full-scale range and the resolution it gives)",
    "representative": "a representative specification level, not one part's datasheet",
}


@dataclass(frozen=True)
class Spec:
    """One term of a preset.

    Attributes
    ----------
    value : str
        The value with its unit, as an ``IMU.toml`` spells it (``"0.005 deg/s/sqrt(Hz)"``).
    basis : str
        A key of :data:`BASES`.
    source : str
        Where it comes from: document and revision, table or section, and the source's own words.
    checked : bool
        True if the number was read against a stored copy of the source when it was entered
        (issue 38); False for values transcribed earlier and not re-read since.
    """

    value: str
    basis: str
    source: str
    checked: bool = False


@dataclass(frozen=True)
class Preset:
    """A named IMU: its document, grade and terms.

    Attributes
    ----------
    document : str
        The part's datasheet (name, number, revision), or what the preset stands for.
    grade : str
        ``"consumer"``, ``"industrial"``, ``"tactical"`` or ``"ideal"``.
    gyro, accel : dict of str to Spec
        The terms per triad (keys are ``IMU.toml`` keys).
    notes : tuple of str
        What the datasheet specifies that the preset does not carry, and why.
    """

    document: str
    grade: str
    gyro: dict[str, Spec] = field(default_factory=dict)
    accel: dict[str, Spec] = field(default_factory=dict)
    notes: tuple[str, ...] = ()


_MPU = "InvenSense PS-MPU-6000A-00 rev. 3.4 (2013)"
_MPU_G = f"{_MPU}, §6.1 Gyroscope Specifications (p. 12)"
_MPU_A = f"{_MPU}, §6.2 Accelerometer Specifications (p. 13)"
_BNO = "Bosch BST-BNO055-DS000"
_BMI = "Bosch BST-BMI088-DS001 rev. 1.4"
_ADIS = "Analog Devices ADIS16470 data sheet rev. C"

PRESET_SPECS: dict[str, Preset] = {
    "ideal": Preset("no errors: the reference for the algorithms' own error", "ideal"),
    # the sensor named by Marusenkova 2020; fusion output up to 100 Hz
    "BNO055": Preset(
        f"{_BNO} (rev. 1.4, 2016, has the same tables)", "consumer",
        gyro={
            "noise_density": Spec("0.014 deg/s/sqrt(Hz)", "datasheet",
                                  f"{_BNO}, table 0-2 (electrical characteristics): noise "
                                  "density"),
            "bias": Spec("1 deg/s", "datasheet",
                         f"{_BNO}, table 0-2: zero-rate offset, typ. ±1 °/s"),
            "range": Spec("2000 deg/s", "setting",
                          f"{_BNO} rev. 1.4, table 3-21: the 2000 dps range", checked=True),
            "resolution": Spec("0.0625 deg/s", "setting",
                               f"{_BNO} rev. 1.4, table 3-22: 1 dps = 16 LSB", checked=True),
        },
        accel={
            "noise_density": Spec("150 ug/sqrt(Hz)", "datasheet",
                                  f"{_BNO}, table 0-2: noise density"),
            "bias": Spec("80 mg", "datasheet", f"{_BNO}, table 0-2: zero-g offset, typ. ±80 mg"),
            "range": Spec("16 g", "setting", f"{_BNO} rev. 1.4, table 3-16: the 16G range",
                          checked=True),
            "resolution": Spec("1 mg", "setting",
                               f"{_BNO}, table 3-17: 1 mg = 1 LSB (the output unit; the "
                               "accelerometer is 14-bit)"),
        },
        notes=("No bias instability for either triad: the datasheet gives none and no "
               "Allan-variance characterisation of the part was found; answers warn.",
               "The gyro's g-sensitivity, the sensitivity tolerances and the temperature "
               "coefficients of table 0-2 were not transcribed (the table was not re-read).")),
    "MPU-6050": Preset(
        f"{_MPU} (MPU-6000/MPU-6050 product specification)", "consumer",
        gyro={
            "noise_density": Spec("0.005 deg/s/sqrt(Hz)", "datasheet",
                                  f"{_MPU_G}: rate noise spectral density at 10 Hz "
                                  "(FS_SEL=0)", checked=True),
            "bias": Spec("20 deg/s", "datasheet",
                         f"{_MPU_G}: initial ZRO tolerance ±20 °/s (25 °C)", checked=True),
            "bias_instability": Spec(
                "0.0012 deg/s", "typical",
                "Allan deviation of one MPU6050 logged at 500 Hz, as its user reported it in "
                "robotics.stackexchange.com question 8860, 'Angle Random Walk vs. Rate Noise "
                "Density (MPU6050)': bias instability 0.0012 °/s (4.3 °/h), ARW 0.003 °/√s; a "
                "single unit and a Q&A post, not peer-reviewed. Of the same order: 4.6 °/h (τ = "
                "500 s) for the MPU-6000 in Greenheck, 'Design and Characterization of a Low "
                "Cost MEMS IMU Cluster for Precision Navigation', MS thesis, Marquette "
                "University, 2015, §2.2 — as quoted in AirSim's ImuSimpleParams.hpp, not read "
                "in the thesis itself", checked=True),
            "scale_factor": Spec("3 %", "datasheet",
                                 f"{_MPU_G}: sensitivity scale factor tolerance ±3 % (25 °C)",
                                 checked=True),
            "misalignment": Spec("2 %", "datasheet", f"{_MPU_G}: cross-axis sensitivity ±2 %",
                                 checked=True),
            "g_sensitivity": Spec("0.1 deg/s/g", "datasheet",
                                  f"{_MPU_G}: linear acceleration sensitivity 0.1 °/s/g "
                                  "(static)", checked=True),
            "range": Spec("2000 deg/s", "setting", f"{_MPU_G}: full-scale range FS_SEL=3",
                          checked=True),
            "resolution": Spec("0.061 deg/s", "setting",
                               f"{_MPU_G}: 16.4 LSB/(°/s) at FS_SEL=3", checked=True),
        },
        accel={
            "noise_density": Spec("400 ug/sqrt(Hz)", "datasheet",
                                  f"{_MPU_A}: power spectral density at 10 Hz (AFS_SEL=0, "
                                  "ODR 1 kHz)", checked=True),
            "bias": Spec("50 mg", "datasheet",
                         f"{_MPU_A}: zero-g output, initial calibration tolerance ±50 mg (X, "
                         "Y; ±80 mg Z)", checked=True),
            "scale_factor": Spec("3 %", "datasheet",
                                 f"{_MPU_A}: sensitivity, initial calibration tolerance ±3 %",
                                 checked=True),
            "misalignment": Spec("2 %", "datasheet", f"{_MPU_A}: cross-axis sensitivity ±2 %",
                                 checked=True),
            "range": Spec("16 g", "setting", f"{_MPU_A}: full-scale range AFS_SEL=3",
                          checked=True),
            "resolution": Spec("0.488 mg", "setting", f"{_MPU_A}: 2048 LSB/g at AFS_SEL=3",
                               checked=True),
        },
        notes=("No accelerometer bias instability: the datasheet gives none and no "
               "Allan-variance characterisation of the part was found; answers warn.",
               "Not carried (no such term in imunav): ZRO variation over temperature ±20 °/s "
               "(−40 to 85 °C), zero-g change ±35 mg X, Y / ±60 mg Z (0 to 70 °C), scale-factor "
               "variation over temperature ±2 % (gyro) and ±0.02 %/°C (accel), nonlinearity "
               "0.2 % (gyro) and 0.5 % (accel), power-supply sensitivity.",
               "Settings, not errors: the digital low-pass filter (5–256 Hz gyro, 5–260 Hz "
               "accel) and the output rates (4–8000 Hz gyro, 4–1000 Hz accel). The noise "
               "densities are specified at the smallest ranges (FS_SEL=0, AFS_SEL=0).")),
    "BMI088": Preset(
        _BMI, "consumer",
        gyro={
            "noise_density": Spec("0.014 deg/s/sqrt(Hz)", "datasheet",
                                  f"{_BMI}, §1 specification, gyroscope: rate noise density"),
            "bias": Spec("1 deg/s", "datasheet",
                         f"{_BMI}, §1 specification, gyroscope: zero-rate offset ±1 °/s"),
            "bias_instability": Spec("2 deg/h", "datasheet",
                                     f"{_BMI}, §1 specification, gyroscope: bias stability "
                                     "2 °/h"),
            "range": Spec("2000 deg/s", "setting",
                          "BST-BMI088-DS001 rev. 1.3, §5.5.2: ±32767 LSB = ±2000 °/s in the "
                          "2000 °/s range", checked=True),
            "resolution": Spec("0.061 deg/s", "setting",
                               "BST-BMI088-DS001 rev. 1.3, §5.5.2: 2000 °/s / 32767 LSB",
                               checked=True),
        },
        accel={
            "noise_density": Spec("175 ug/sqrt(Hz)", "datasheet",
                                  f"{_BMI}, §1 specification, accelerometer: noise density "
                                  "(x, y)"),
            "bias": Spec("20 mg", "datasheet",
                         f"{_BMI}, §1 specification, accelerometer: zero-g offset ±20 mg"),
            "range": Spec("24 g", "setting", f"{_BMI}, §1: ±24 g range"),
            "resolution": Spec("0.732 mg", "setting",
                               f"{_BMI}, §1: 1365 LSB/g at ±24 g (the register formula of "
                               "§5.3.4 in rev. 1.3 gives 16 g full scale instead)"),
        },
        notes=("No accelerometer bias instability: the datasheet gives none and no "
               "Allan-variance characterisation of the part was found; answers warn.",
               "The specification tables were not re-read for issue 38: the g-sensitivity, "
               "sensitivity tolerances, cross-axis sensitivities and temperature coefficients "
               "it may specify are not carried.")),
    "ADIS16470": Preset(
        f"{_ADIS} (2 kHz output)", "industrial",
        gyro={
            "noise_density": Spec("0.34 deg/sqrt(h)", "datasheet",
                                  f"{_ADIS}, table 1: angle random walk 0.34 °/√h"),
            "bias_instability": Spec("8 deg/h", "datasheet",
                                     f"{_ADIS}, table 1: in-run bias stability 8 °/h"),
            "misalignment": Spec("0.05 deg", "datasheet",
                                 f"{_ADIS}, table 1: misalignment, axis to axis ±0.05°"),
            "range": Spec("2000 deg/s", "setting", f"{_ADIS}, table 1: dynamic range ±2000 °/s"),
        },
        accel={
            "noise_density": Spec("0.037 m/s/sqrt(h)", "datasheet",
                                  f"{_ADIS}, table 1: velocity random walk 0.037 m/s/√h"),
            "bias_instability": Spec("13 ug", "datasheet",
                                     f"{_ADIS}, table 1: in-run bias stability 13 µg"),
            "misalignment": Spec("0.05 deg", "datasheet",
                                 f"{_ADIS}, table 1: misalignment, axis to axis ±0.05°"),
            "range": Spec("40 g", "setting", f"{_ADIS}, table 1: dynamic range ±40 g"),
        },
        notes=("Table 1 was not re-read for issue 38: its sensitivity error, bias "
               "repeatability (turn-on bias), linear-acceleration effect on the gyro bias and "
               "temperature coefficients are not carried.",)),
    # HG1700-class specification levels, not one part
    "tactical": Preset(
        "a representative tactical-grade IMU (HG1700-class specification levels, not one "
        "part's datasheet)", "tactical",
        gyro={
            "noise_density": Spec("0.125 deg/sqrt(h)", "representative", "ARW 0.125 °/√h"),
            "bias": Spec("1 deg/h", "representative", "turn-on bias 1 °/h"),
            "bias_instability": Spec("1 deg/h", "representative", "bias stability 1 °/h"),
            "bias_correlation_time": Spec("3600 s", "representative",
                                          "imunav's choice: a Gauss–Markov bias of 1 h"),
            "scale_factor": Spec("150 ppm", "representative", "scale factor 150 ppm"),
        },
        accel={
            "noise_density": Spec("0.05 m/s/sqrt(h)", "representative", "VRW 0.05 m/s/√h"),
            "bias": Spec("1 mg", "representative", "turn-on bias 1 mg"),
            "bias_instability": Spec("50 ug", "representative", "bias stability 50 µg"),
            "bias_correlation_time": Spec("3600 s", "representative",
                                          "imunav's choice: a Gauss–Markov bias of 1 h"),
            "scale_factor": Spec("300 ppm", "representative", "scale factor 300 ppm"),
        },
        notes=("Not one part: representative levels for a tactical-grade IMU.",)),
}

#: The presets as ``IMU.toml`` tables: ``{name: {"gyro": {key: value}, "accel": {…}}}``.
PRESETS: dict[str, dict] = {
    name: {"gyro": {k: s.value for k, s in p.gyro.items()},
           "accel": {k: s.value for k, s in p.accel.items()}}
    for name, p in PRESET_SPECS.items()
}


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def preset_table() -> str:
    """The docs' preset page (``docs/presets.md``), written from :data:`PRESET_SPECS`.

    Regenerate the page with ``python -c "from imunav.sensors.presets import preset_table;
    print(preset_table(), end='')" > docs/presets.md``; ``tests/sensors/test_models.py`` fails when
    it differs.

    Returns
    -------
    str
        Markdown (MyST; an orphan page until a toctree lists it): every preset, every term,
        its value, unit, basis and source.
    """
    lines = ["---", "orphan: true", "---", "", "# IMU presets", "",
             "Generated from `imunav.sensors.presets.PRESET_SPECS` by `preset_table()`; do not "
             "edit by hand (`tests/sensors/test_models.py` compares this page with the code).", "",
             "Each term: its value and unit as an `IMU.toml` spells it, what it rests on, and "
             "its source. *checked*: the number was read against a stored copy of the source "
             "when it was entered (issue 38); *not re-read*: transcribed earlier, not checked "
             "since. Turn-on bias, scale factor and misalignment are used as 1σ.", "",
             "Bases:", ""]
    lines += [f"- **{k}**: {v}" for k, v in BASES.items()]
    lines += ["", "A preset, or any IMU model, without a `bias_instability` for a triad that "
              "has errors answers every assessment and outage question with a `warning:` that "
              "names the missing bias instability: a term the datasheet is silent on is not "
              "zero.", ""]
    for name, p in PRESET_SPECS.items():
        lines += [f"## {name}", "", f"{p.document} — {p.grade}.", ""]
        if not (p.gyro or p.accel):
            lines += ["No error terms.", ""]
            continue
        lines += ["| triad | term | value | unit | basis | source | checked |",
                  "|---|---|---|---|---|---|---|"]
        for triad, terms in (("gyro", p.gyro), ("accel", p.accel)):
            for key, s in terms.items():
                number, _, unit = s.value.partition(" ")
                lines.append(f"| {triad} | `{key}` | {number} | {_cell(unit)} | {s.basis} | "
                             f"{_cell(s.source)} | {'checked' if s.checked else 'not re-read'} |")
        lines.append("")
        lines += [f"- {_cell(n)}" for n in p.notes]
        if p.notes:
            lines.append("")
    return "\n".join(lines)
