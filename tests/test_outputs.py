"""Solution outputs: ``FilterSolution.write`` / ``LogRun.write``
in CSV, RTKLIB .pos, KML, GPX and GeoJSON, each file read back by an
independent reader (numpy, memsnav's own .pos reader, fastkml, gpxpy,
geojson) and compared with the solution's own columns to the written
precision; the DataFrames; the plot helpers; the refusals."""

from __future__ import annotations

import datetime as dt
import json
import sys
import warnings

import gpxpy
import matplotlib
import numpy as np
import pytest

import memsnav as mn

with warnings.catch_warnings():
    # fastkml warns when lxml is absent (it then parses with the standard library).
    warnings.simplefilter("ignore", UserWarning)
    from fastkml import kml as fastkml_kml
import geojson

matplotlib.use("Agg")

#: GPS time of 2025-08-28 17:30:00 GPST: GPS − UTC is 18 s then.
T0 = 2381 * 604_800.0 + 4 * 86_400.0 + 63_000.0
GPS_EPOCH = dt.datetime(1980, 1, 6, tzinfo=dt.UTC)


def _utc(gps_time_s: float) -> dt.datetime:
    """UTC of a 2025 GPS time, independently of the core: less 18 leap
    seconds, rounded to the millisecond as written."""
    return GPS_EPOCH + dt.timedelta(milliseconds=round(gps_time_s * 1000) - 18_000)


@pytest.fixture(scope="module")
def run():
    """A 60 s simulated drive at 100 Hz near Toulouse, 1 Hz fixes, on 2025 GPS time."""
    trajectory = mn.Trajectory.random(60.0, seed=3, stationary_start=10.0)
    t = trajectory.time + T0
    k = np.arange(0, len(t), 100)
    fixes = mn.fixes_from_solution(
        t[k],
        trajectory.position_geodetic()[k],
        np.full((len(k), 3), 0.5),
        velocity_ned=trajectory.velocity_ned()[k],
        velocity_std_ned=np.full((len(k), 3), 0.1),
        seed=1,
    )
    return mn.navigate_log(t, trajectory.specific_force, trajectory.angular_rate, fixes)


def _map_rows(run, rate_hz=10.0):
    columns = run.columns(rate_hz)
    assert len(columns["gps_time_s"]) == len(mn._memsnav.decimate(run.time, rate_hz))
    return columns


def test_gpx_read_by_gpxpy(run, tmp_path):
    path = tmp_path / "drive.gpx"
    run.write(path)
    gpx = gpxpy.parse(path.read_text(encoding="utf-8"))
    assert gpx.version == "1.1" and gpx.creator == "memsnav"
    (track,) = gpx.tracks
    assert track.name == "drive"
    points = track.segments[0].points
    rows = _map_rows(run)
    # The run starts at its alignment, about 1 s in: 10 Hz over the rest.
    assert len(points) == len(rows["gps_time_s"]) > 580
    np.testing.assert_allclose([p.latitude for p in points], rows["lat_deg"], rtol=0, atol=5e-10)
    np.testing.assert_allclose([p.longitude for p in points], rows["lon_deg"], rtol=0, atol=5e-10)
    np.testing.assert_allclose([p.elevation for p in points], rows["height_m"], rtol=0, atol=5e-5)
    assert [p.time for p in points] == [_utc(t) for t in rows["gps_time_s"]]
    assert points[0].time.isoformat().startswith("2025-08-28T17:29:4")


def test_kml_read_by_fastkml(run, tmp_path):
    path = tmp_path / "drive.kml"
    run.write(path, name="a drive & more", rate_hz=2.0)
    document = fastkml_kml.KML.parse(path).features[0]
    assert document.name == "a drive & more"
    track, start, end = document.features
    rows = _map_rows(run, 2.0)
    # fastkml's own coordinates (its pygeoif geometry drops repeated points).
    coordinates = np.array(track.kml_geometry.kml_coordinates.coords)
    assert coordinates.shape == (len(rows["gps_time_s"]), 3)
    assert 115 < len(coordinates) <= 120  # 2 Hz
    np.testing.assert_allclose(coordinates[:, 0], rows["lon_deg"], rtol=0, atol=5e-10)
    np.testing.assert_allclose(coordinates[:, 1], rows["lat_deg"], rtol=0, atol=5e-10)
    np.testing.assert_allclose(coordinates[:, 2], rows["height_m"], rtol=0, atol=5e-5)
    assert (start.name, end.name) == ("start", "end")
    np.testing.assert_array_equal(start.geometry.coords[0], coordinates[0])
    np.testing.assert_array_equal(end.geometry.coords[0], coordinates[-1])
    assert start.times.timestamp.dt == _utc(rows["gps_time_s"][0])
    assert track.times.end.dt.replace(microsecond=0) == _utc(rows["gps_time_s"][-1]).replace(
        microsecond=0
    )


def test_geojson_read_by_geojson(run, tmp_path):
    path = tmp_path / "drive.json"
    run.write(path)
    text = path.read_text(encoding="utf-8")
    collection = geojson.loads(text)
    assert collection.is_valid, collection.errors()
    assert collection["type"] == "FeatureCollection"
    (feature,) = collection["features"]
    assert feature["geometry"]["type"] == "LineString"
    rows = _map_rows(run)
    # The geojson package rounds coordinates to 6 decimals; the file's own
    # (9 decimals) through the standard library's parser.
    parsed = np.array(feature["geometry"]["coordinates"])
    coordinates = np.array(json.loads(text)["features"][0]["geometry"]["coordinates"])
    np.testing.assert_allclose(parsed, coordinates, rtol=0, atol=5e-6)
    # RFC 7946: longitude, latitude, height.
    np.testing.assert_allclose(coordinates[:, 0], rows["lon_deg"], rtol=0, atol=5e-10)
    np.testing.assert_allclose(coordinates[:, 1], rows["lat_deg"], rtol=0, atol=5e-10)
    np.testing.assert_allclose(coordinates[:, 2], rows["height_m"], rtol=0, atol=5e-5)
    properties = feature["properties"]
    assert properties["name"] == "drive"
    times = [dt.datetime.fromisoformat(s) for s in properties["coordTimes"]]
    assert times == [_utc(t) for t in rows["gps_time_s"]]
    np.testing.assert_allclose(properties["gps_time_s"], rows["gps_time_s"], rtol=0, atol=5e-5)


def test_csv_and_pos_read_back(run, tmp_path):
    run.write(tmp_path / "drive.csv")
    table = np.genfromtxt(tmp_path / "drive.csv", delimiter=",", names=True)
    columns = run.columns()
    assert list(table.dtype.names) == list(columns)
    assert len(table) == len(run)
    for name, values in columns.items():
        decimals = {"gps_time_s": 4, "lat_deg": 9, "lon_deg": 9, "height_m": 4}.get(name, 5)
        np.testing.assert_allclose(table[name], values, rtol=0, atol=0.51 * 10.0**-decimals)
    lla = np.asarray(run.geodetic)
    np.testing.assert_allclose(np.radians(columns["lat_deg"]), lla[:, 0], rtol=0, atol=1e-15)

    run.write(tmp_path / "drive.pos")
    pos = mn.read_pos(tmp_path / "drive.pos")
    rows = _map_rows(run)
    np.testing.assert_allclose(pos.gps_time, rows["gps_time_s"], rtol=0, atol=5e-4)
    np.testing.assert_allclose(
        np.degrees(pos.lla[:, :2]),
        np.column_stack([rows["lat_deg"], rows["lon_deg"]]),
        rtol=0,
        atol=5e-10,
    )
    np.testing.assert_allclose(pos.lla[:, 2], rows["height_m"], rtol=0, atol=5e-5)
    velocity = np.column_stack([rows["vn_m_s"], rows["ve_m_s"], rows["vd_m_s"]])
    np.testing.assert_allclose(pos.velocity_ned, velocity, rtol=0, atol=5e-6)
    std = np.column_stack([rows["sdn_m"], rows["sde_m"], rows["sdd_m"]])
    np.testing.assert_allclose(pos.std_ned, std, rtol=0, atol=5e-5)


def test_filter_solution_writes_at_the_imu(run, tmp_path):
    solution = run.solution
    columns = solution.columns(10.0)
    keep = mn._memsnav.decimate(solution.time, 10.0)
    lla = np.asarray(mn.ecef_to_geodetic(solution.position_ecef[keep]))
    np.testing.assert_allclose(np.radians(columns["lat_deg"]), lla[:, 0], rtol=0, atol=1e-14)
    np.testing.assert_allclose(columns["height_m"], lla[:, 2], rtol=0, atol=1e-6)
    solution.write(tmp_path / "imu.gpx", format="GPX")
    points = gpxpy.parse((tmp_path / "imu.gpx").read_text()).tracks[0].segments[0].points
    np.testing.assert_allclose([p.latitude for p in points], columns["lat_deg"], atol=5e-10)


def test_data_frames(run, monkeypatch):
    pandas = pytest.importorskip("pandas")
    polars = pytest.importorskip("polars")
    columns = run.columns(1.0)
    frame = run.to_pandas(rate_hz=1.0)
    assert isinstance(frame, pandas.DataFrame) and list(frame.columns) == list(columns)
    np.testing.assert_array_equal(frame["sdn_m"].to_numpy(), columns["sdn_m"])
    frame = run.solution.to_polars()
    assert isinstance(frame, polars.DataFrame) and frame.height == len(run)
    np.testing.assert_array_equal(frame["yaw_deg"].to_numpy(), run.solution.columns()["yaw_deg"])
    monkeypatch.setitem(sys.modules, "polars", None)
    with pytest.raises(ImportError, match=r"to_polars\(\) needs polars.*pip install polars"):
        run.to_polars()


def test_bad_arguments_and_foreign_files(run, tmp_path):
    with pytest.raises(ValueError, match=r'^format: "shp" is not a format .*"csv", "pos", "kml"'):
        run.write(tmp_path / "x.shp", format="shp")
    with pytest.raises(ValueError, match=r"^format: not given, and the extension of .*x\.txt"):
        run.write(tmp_path / "x.txt")
    with pytest.raises(OSError, match="does not exist; create it first"):
        run.write(tmp_path / "missing" / "x.kml")
    with pytest.raises(ValueError, match=r"^rate_hz: must be a positive number"):
        run.write(tmp_path / "x.kml", rate_hz=0.0)
    mine = tmp_path / "notes.kml"
    mine.write_text("<kml>my own notes</kml>")
    with pytest.raises(ValueError, match="exists and is not a solution file memsnav wrote"):
        run.write(mine)
    assert mine.read_text() == "<kml>my own notes</kml>"
    run.write(mine, overwrite=True)
    run.write(mine)  # now memsnav's: replaced without asking
    assert "written by memsnav" in mine.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.kml"]


def test_plot_helpers_draw_the_track_and_the_errors(run):
    import matplotlib.pyplot as plt

    ax = mn.plot_track(run, rate_hz=10.0, outages=[(T0 + 20.0, T0 + 30.0)], label="memsnav")
    track, outage = ax.get_lines()
    ned = np.asarray(mn.ecef_to_ned(run.position_ecef, run.position_ecef[0]))
    keep = mn._memsnav.decimate(run.time, 10.0)
    np.testing.assert_allclose(track.get_xdata(), ned[keep, 1])
    np.testing.assert_allclose(track.get_ydata(), ned[keep, 0])
    assert len(outage.get_xdata()) == 100
    plt.close(ax.figure)

    truth_time = run.time[::50]
    score = run.score(truth_time, run.position_ecef[::50] + np.array([1.0, 0.0, 0.0]))
    axes = mn.plot_errors(score["time"], score["error_ned"], score["std_ned"], t0=T0)
    # The size of the error on a log scale (below 1 cm drawn at 1 cm) and the 3σ bound.
    error, bound = axes[2].get_lines()
    np.testing.assert_allclose(
        error.get_ydata(), np.maximum(np.abs(score["error_ned"][:, 2]), 0.01)
    )
    np.testing.assert_allclose(bound.get_ydata(), 3 * score["std_ned"][:, 2])
    assert bound.get_gid() == "bound" and axes[2].get_yscale() == "log"
    np.testing.assert_allclose(error.get_xdata(), score["time"] - T0)
    plt.close(axes[0].figure)
