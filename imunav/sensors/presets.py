"""IMU presets: typical datasheet values, each with its source.

Values are the datasheets' typical figures as transcribed for imunav (document numbers
given); turn-on bias, scale factor and misalignment are used as 1σ. Where a datasheet gives no
figure for a term (often bias instability for consumer parts), the term is absent rather than
invented. Check the numbers against the revision of the part you use before relying on them.

May import: nothing from imunav (data only).
"""

PRESETS: dict[str, dict] = {
    "ideal": {"gyro": {}, "accel": {}},
    # Bosch BNO055, data sheet BST-BNO055-DS000 (the sensor named by Marusenkova 2020);
    # fusion output up to 100 Hz.
    "BNO055": {
        "gyro": {"noise_density": "0.014 deg/s/sqrt(Hz)",   # DS000 tab. 0-2: noise density
                 "bias": "1 deg/s",                         # zero-rate offset, typ. ±1 °/s
                 "range": "2000 deg/s", "resolution": "0.0625 deg/s"},  # 16 LSB/(°/s)
        "accel": {"noise_density": "150 ug/sqrt(Hz)",       # DS000 tab. 0-1: noise density
                  "bias": "80 mg",                          # zero-g offset, typ. ±80 mg
                  "range": "16 g", "resolution": "1 mg"},   # 1 LSB = 1 mg
    },
    # InvenSense MPU-6050, product specification PS-MPU-6000A-00 rev. 3.4.
    "MPU-6050": {
        "gyro": {"noise_density": "0.005 deg/s/sqrt(Hz)",   # rate noise spectral density
                 "bias": "20 deg/s",                        # initial ZRO tolerance ±20 °/s
                 "scale_factor": "3 %",                     # sensitivity tolerance ±3 %
                 "misalignment": "2 %",                     # cross-axis sensitivity ±2 %
                 "range": "2000 deg/s", "resolution": "0.061 deg/s"},   # 16.4 LSB/(°/s)
        "accel": {"noise_density": "400 ug/sqrt(Hz)",       # noise power spectral density
                  "bias": "50 mg",                          # zero-g output ±50 mg (x, y)
                  "scale_factor": "3 %",                    # initial calibration tolerance
                  "misalignment": "2 %",                    # cross-axis sensitivity ±2 %
                  "range": "16 g", "resolution": "0.488 mg"},           # 2048 LSB/g
    },
    # Bosch BMI088, data sheet BST-BMI088-DS001 rev. 1.4.
    "BMI088": {
        "gyro": {"noise_density": "0.014 deg/s/sqrt(Hz)",   # rate noise density
                 "bias": "1 deg/s",                         # zero-rate offset ±1 °/s
                 "bias_instability": "2 deg/h",             # bias stability 2 °/h
                 "range": "2000 deg/s", "resolution": "0.061 deg/s"},
        "accel": {"noise_density": "175 ug/sqrt(Hz)",       # noise density (x, y)
                  "bias": "20 mg",                          # zero-g offset ±20 mg
                  "range": "24 g", "resolution": "0.732 mg"},
    },
    # Analog Devices ADIS16470, data sheet rev. C (tactical-class MEMS IMU, 2 kHz output).
    "ADIS16470": {
        "gyro": {"noise_density": "0.34 deg/sqrt(h)",       # angle random walk 0.34 °/√h
                 "bias_instability": "8 deg/h",             # in-run bias stability 8 °/h
                 "misalignment": "0.05 deg",                # axis-to-axis misalignment
                 "range": "2000 deg/s"},
        "accel": {"noise_density": "0.037 m/s/sqrt(h)",     # velocity random walk
                  "bias_instability": "13 ug",              # in-run bias stability 13 µg
                  "misalignment": "0.05 deg",
                  "range": "40 g"},
    },
    # A representative tactical-grade IMU (HG1700-class specification levels, not one part):
    # 1 °/h gyro bias stability, 0.125 °/√h ARW, 1 mg accel bias, 0.05 m/s/√h VRW.
    "tactical": {
        "gyro": {"noise_density": "0.125 deg/sqrt(h)", "bias": "1 deg/h",
                 "bias_instability": "1 deg/h", "bias_correlation_time": "3600 s",
                 "scale_factor": "150 ppm"},
        "accel": {"noise_density": "0.05 m/s/sqrt(h)", "bias": "1 mg",
                  "bias_instability": "50 ug", "bias_correlation_time": "3600 s",
                  "scale_factor": "300 ppm"},
    },
}
