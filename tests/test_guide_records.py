"""The records behind the guides' and the reference's figures on IMU and
GNSS files (docs/gnss_file_measurements.py), run again on the shared
data: each agrees with its record, docs/data/<name>.json, within half the
last digit the pages show."""

from run_record import check_run


def test_the_tag_clocks_are_the_record():
    """docs/reference/readers.md's IMU clocks (two full logs, ~2 s): the
    arrival lags to the millisecond, the rates to the ppm, the misread's
    drift to 0.05 %. Every line arrives after it was taken, within the
    spread; read as the file's LF bytes the tags make the IMU clock look
    about one byte per line (~45) slow, which no crystal is."""
    per_log = {"*": 5e-4, "rate_ppm": 0.5, "misread_rate_percent": 0.05}
    fresh = check_run("tag_clocks", {"*": per_log}, needs_data=True)
    for clock in fresh.values():
        assert 0.0 < clock["lag_spread_first_50s_s"] <= clock["lag_spread_s"]
        assert 0.0 < clock["lag_spread_after_1s_s"] <= clock["lag_spread_s"]
        assert 0.0 < clock["rate_ppm"] < 100.0  # a consumer crystal's tolerance
        assert 1.0 < clock["misread_rate_percent"] < 5.0
