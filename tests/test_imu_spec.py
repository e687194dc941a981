"""An IMU spec from a data sheet (``memsnav_core::sensors::datasheet``, the
``[imu_spec]`` table): the conversions against hand-computed values, the
presets as data sheets, and the checks naming ``imu_spec.key``."""

from __future__ import annotations

import math

import pytest

import memsnav as mn

#: The consumer preset's figures (the Bosch BMI088 class of
#: crates/memsnav-core/src/sensors/presets.rs) in data-sheet keys.
CONSUMER = {
    "accel_turn_on_bias_mg": 20.0,
    "accel_scale_factor_pct": 1.0,
    "accel_cross_axis_pct": 1.0,
    "accel_nonlinearity_ug_g2": 100.0,
    "accel_noise_density_ug_sqrt_hz": 175.0,
    "accel_bias_markov_std_ug": 100.0,
    "accel_bias_correlation_time_s": 300.0,
    "gyro_turn_on_bias_deg_s": 1.0,
    "gyro_scale_factor_pct": 1.0,
    "gyro_cross_axis_pct": 1.0,
    "gyro_g_sensitivity_deg_s_g": 0.05,
    "gyro_noise_density_deg_s_sqrt_hz": 0.014,
    "gyro_bias_markov_std_deg_h": 2.0,
    "gyro_bias_correlation_time_s": 300.0,
}

#: The worked example of the navigate guide: the Analog Devices ADIS16465-1
#: data sheet's figures, over the "industrial" preset.
ADIS16465 = {
    "gyro_arw_deg_sqrt_h": 0.15,
    "gyro_bias_instability_deg_h": 2.0,
    "gyro_bias_correlation_time_s": 100.0,
    "gyro_misalignment_deg": 0.05,
    "accel_vrw_m_s_sqrt_h": 0.037,
    "accel_bias_instability_ug": 3.6,
    "accel_bias_correlation_time_s": 100.0,
    "accel_misalignment_deg": 0.05,
}


def test_the_worked_example_by_hand():
    """Each figure converted as the navigate guide shows it: ARW 0.15 °/√h
    / 60 = 0.0025 °/√s = 4.3633e-5 rad/√s; VRW 0.037 m/s/√h / 60 =
    6.1667e-4 m/s/√s; in-run bias stability 2 °/h / 0.617364 = 3.2396 °/h
    = 1.5706e-5 rad/s and 3.6 µg / 0.617364 = 5.8312 µg = 5.7185e-5 m/s²;
    0.05° = 8.7266e-4 rad. The terms the sheet does not give are the
    industrial preset's."""
    spec = mn.imu_spec_from_datasheet(ADIS16465, base="industrial")
    assert spec["gyro_noise_density"] == pytest.approx(4.3633e-5, rel=1e-4)
    assert spec["accel_noise_density"] == pytest.approx(6.1667e-4, rel=1e-4)
    assert spec["gyro_bias_instability"] == pytest.approx(1.5706e-5, rel=1e-4)
    assert spec["accel_bias_instability"] == pytest.approx(5.7185e-5, rel=1e-4)
    assert spec["gyro_misalignment_std"] == pytest.approx(8.7266e-4, rel=1e-4)
    assert spec["gyro_bias_correlation_time"] == 100.0
    industrial = mn.ImuModel.preset("industrial").spec
    for key in (
        "accel_bias_std",
        "gyro_bias_std",
        "gyro_scale_factor_std",
        "gyro_g_sensitivity_std",
    ):
        assert spec[key] == industrial[key], key
    # The floor/σ ratio is the Gauss-Markov process's Allan peak: a
    # process of σ = 1 peaks at 0.617364 (the closed form, checked here).
    x = 1.8926178

    def peak(y: float) -> float:
        return (2.0 / y) * (1.0 - (3.0 - 4.0 * math.exp(-y) + math.exp(-2.0 * y)) / (2.0 * y))

    assert math.sqrt(peak(x)) == pytest.approx(0.617364, abs=1e-6)
    assert peak(x) > max(peak(x * 0.99), peak(x * 1.01))


def test_a_preset_written_as_a_data_sheet_is_the_preset():
    spec = mn.imu_spec_from_datasheet(CONSUMER, base="tactical")
    consumer = mn.ImuModel.preset("consumer").spec
    for key, value in consumer.items():
        if not key.endswith("quantization"):  # not a data-sheet key
            assert spec[key] == value, key


def test_keys_and_values_are_checked_by_name():
    meant = r'imu_spec.gyro_arw: unknown key \(did you mean "gyro_arw_deg_sqrt_h"\?\); \[imu_spec\]'
    with pytest.raises(ValueError, match=meant):
        mn.imu_spec_from_datasheet({"gyro_arw": 0.1})
    with pytest.raises(ValueError, match=r"imu_spec.gyro_arw_deg_sqrt_h: must be finite and non"):
        mn.imu_spec_from_datasheet({"gyro_arw_deg_sqrt_h": float("nan")})
    with pytest.raises(ValueError, match=r"imu_spec.gyro_arw_deg_sqrt_h: must be a number"):
        mn.imu_spec_from_datasheet({"gyro_arw_deg_sqrt_h": "0.1"})
    with pytest.raises(ValueError, match=r"imu_spec.accel_bias_correlation_time_s: is needed"):
        mn.imu_spec_from_datasheet({"accel_bias_instability_mg": 0.05})
    with pytest.raises(ValueError, match=r"gives the same quantity as imu_spec.accel_scale_factor"):
        mn.imu_spec_from_datasheet(
            {"accel_scale_factor_ppm": 300.0, "accel_scale_factor_pct": 0.03}
        )
    with pytest.raises(ValueError, match=r"base: unknown preset 'cheap'; expected one of"):
        mn.imu_spec_from_datasheet({}, base="cheap")
    assert mn.imu_spec_from_datasheet({}) == mn.ImuModel.preset("consumer").spec
    assert set(mn.navigate_settings()["imu_spec"]) >= set(CONSUMER) | set(ADIS16465)
