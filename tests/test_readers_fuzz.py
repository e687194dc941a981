"""Fuzzing the Python faces of the readers (hypothesis): valid
files with bytes flipped, cut, numbers replaced by huge or non-finite ones
and garbage appended give a result or a ``ValueError`` (``ParseError``)
naming the file: never another exception, a crash or a hang. A satellite
record of an SP3 or RINEX observation epoch duplicated, or another
relabelled with its name, is always that error. What
``write_pos`` accepts, ``read_pos`` reads back.

CI runs a fixed, derandomised budget; ``MEMSNAV_FUZZ_EXAMPLES=N`` raises it
and draws new inputs each run (docs/reference/robustness.md). The Rust suite
(``crates/memsnav-core/tests/readers_fuzz.rs``) fuzzes the parsers
themselves far faster; this one covers the bindings and the wrappers.
"""

from __future__ import annotations

import math
import os
import struct
import tempfile
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import memsnav as mn

DATA = Path(__file__).parent / "data"
EX = DATA / "real-imu-gnss"
PUBLIC = DATA / "rinex-public"
LONG = "MEMSNAV_FUZZ_EXAMPLES" in os.environ
FUZZ = settings(
    max_examples=int(os.environ.get("MEMSNAV_FUZZ_EXAMPLES", "40")),
    derandomize=not LONG,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)

SP3 = """#dP2021  4 28  0  0  0.00000000       2 ORBIT IGb14 HLM  COD
+    2   G01G02  0  0  0  0  0  0  0  0  0  0  0  0  0  0  0
%c M  cc GPS ccc cccc cccc cccc cccc ccccc ccccc ccccc ccccc
*  2021  4 28  0  0  0.00000000
PG01  13744.405346 -22569.713946   3524.563484    -35.471733
PG02 -17432.166712   2895.601632 -19885.125497    -19.893412
*  2021  4 28  0  5  0.00000000
PG01  13848.512383 -22211.297941   6208.223406    -35.472146
PG02 -17005.224919   3838.417103 -20029.707301    -19.893417
EOF
"""


KLOBUCHAR = """     3.04           N: GNSS NAV DATA    M: Mixed            RINEX VERSION / TYPE
GPSA   1.1176D-08 -7.4506D-09 -5.9605D-08  1.1921D-07       IONOSPHERIC CORR
GPSB   1.1674D+05 -2.2938D+05 -1.3107D+05  1.0486D+06       IONOSPHERIC CORR
                                                            END OF HEADER
"""


FIXES_CSV = """# fixes
gps_time_s,lat_deg,lon_deg,height_m,cov_nn_m2,cov_ne_m2,cov_nd_m2,cov_ee_m2,cov_ed_m2,cov_dd_m2,vn_m_s,ve_m_s,vd_m_s,std_vn_m_s,std_ve_m_s,std_vd_m_s,quality
1435838094.999,40.0966268,-105.1474483,1601.45,1e-4,2e-5,0,1e-4,0,1.2e-4,-0.002,0.001,0.008,0.058,0.058,0.058,1
1435838095.249,40.0966268,-105.1474483,1601.453,1e-4,0,0,1e-4,0,1.2e-4,,,,,,,2
"""

NMEA = """$GNGGA,120000.00,5130.000000,N,00007.500000,W,4,12,0.9,45.0,M,47.0,M,1.0,0123*74
$GNRMC,120000.00,A,5130.000000,N,00007.500000,W,1.5,90.0,150320,,,R*7F
$GNGST,120000.00,1.0,0.02,0.01,45.0,0.015,0.015,0.03*4A
$GNVTG,90.0,T,,M,1.5,N,2.8,K,R*37
NMEA,$GNGGA,120000.25,5130.000001,N,00007.500001,W,4,12,0.9,45.0,M,47.0,M,1.0,0123*73,1584273618250
NMEA,$GNRMC,120000.25,A,5130.000001,N,00007.500001,W,1.5,90.0,150320,,,R*78,1584273618251
$GNGST,120000.25,1.0,0.02,0.01,45.0,0.015,0.015,0.03*4D
"""


def _head(name: str, lines: int) -> bytes:
    return b"".join((EX / name).read_bytes().splitlines(keepends=True)[:lines])


GNSS_TABLE_HEADER = ",".join(
    ["time_s", "sat_id"]
    + [f"sat_position_ecef_{a}_m" for a in "xyz"]
    + [f"sat_velocity_ecef_{a}_m_s" for a in "xyz"]
    + ["pseudorange_m", "pseudorange_rate_m_s"]
)
GNSS_TABLE = (
    GNSS_TABLE_HEADER
    + """
0,5,-2179862.557,-26154875.769,-3437694.371,325.541,-419.725,3129.012,23052313.867,-120.5
0,13,-5199894.405,-17419269.957,23361281.147,2239.305,700.815,1022.014,23522506.859,
1,5,-2179537.0,-26155295.4,-3434565.4,325.5,-419.7,3129.0,23052193.2,-120.6
"""
)

#: An integrating IMU's log: a preamble, its own column order named by its
#: header, increments in g·s and degrees, FLU axes.
IMU_INCREMENTS = """# exported by another logger
time_s,dang_z,dvel_x,dang_x,dvel_z,dang_y,dvel_y,temp_c
1735.000,0,0,0,0,0,0,21.5
1735.010,0.0012,0.0001,-0.0004,0.01,0.0002,-0.00002,21.5
1735.020,0.0011,0.0001,-0.0003,0.01,0.0002,-0.00001,21.5
1735.031,0.0013,0.0002,-0.0004,0.0101,0.0001,-0.00002,21.6
1735.040,0.0010,0.0001,-0.0005,0.0099,0.0002,0.0,21.6
"""
_BY_NAME = {"t": "time_s", "ax": "dvel_x", "ay": "dvel_y", "az": "dvel_z"}
_BY_NAME |= {"gx": "dang_x", "gy": "dang_y", "gz": "dang_z"}
_BY_NUMBER = {"t": 1, "gz": 2, "ax": 3, "gx": 4, "az": 5, "gy": 6, "ay": 7}
#: An axes rotation given as a matrix: 30° about the vertical.
_YAW_30 = [[0.8660254037844387, -0.5, 0.0], [0.5, 0.8660254037844387, 0.0], [0.0, 0.0, 1.0]]


def _read_increments(path: Path) -> Any:
    return mn.read_imu_csv(
        path, _BY_NAME, accel_unit="g*s", gyro_unit="deg", time_unit="s", axes="FLU",
        header_lines=1,
    )  # fmt: skip


def _read_numbered(path: Path) -> Any:
    return mn.read_imu_csv(
        path, _BY_NUMBER, accel_unit="g*s", gyro_unit="deg", time_unit="s", axes=_YAW_30,
        header_lines=2,
    )  # fmt: skip


#: (seed bytes, file extension, reader) per reader.
READERS: dict[str, tuple[bytes, str, Callable[[Path], Any]]] = {
    "imu_csv": (_head("drive_60s.csv", 20), "csv", mn.read_imu_csv),
    "imu_increments": (IMU_INCREMENTS.encode(), "csv", _read_increments),
    "imu_increments_numbered": (IMU_INCREMENTS.encode(), "csv", _read_numbered),
    "time_tag": ((EX / "walk_head.csv.tag").read_bytes(), "tag", mn.read_time_tag),
    "pos": (_head("walk_head.pos", 12), "pos", mn.read_pos),
    "rinex_obs": ((EX / "walk_head.obs").read_bytes(), "obs", mn.read_rinex_obs),
    "rinex_nav": (_head("walk.nav", 21), "nav", mn.Constellation.from_rinex_nav),
    "klobuchar": (KLOBUCHAR.encode(), "nav", mn.read_klobuchar),
    "sp3": (SP3.encode(), "sp3", mn.read_sp3),
    "fixes_csv": (FIXES_CSV.encode(), "csv", mn.read_fixes_csv),
    "nmea": (NMEA.encode(), "nmea", mn.read_nmea),
    "gnss_table": (GNSS_TABLE.encode(), "csv", mn.GnssMeasurements.from_table),
    "gnsslogger": (
        (DATA / "android-gnsslogger" / "pixel6_excerpt.txt").read_bytes(),
        "txt",
        mn.read_gnsslogger,
    ),
    "ubx": ((EX / "walk_head.ubx").read_bytes(), "ubx", mn.read_ubx),
    "rinex2_obs": ((PUBLIC / "14601736.18o").read_bytes(), "18o", mn.read_rinex_obs),
    # RINEX 4.00: 4 LNAV and 2 CNAV records of convert's output.
    "rinex4_nav": (_head("walk.rnx", 60), "rnx", mn.read_broadcast_nav),
    "glonass_nav": (
        b"".join((PUBLIC / "brdc1360_excerpt.20g").read_bytes().splitlines(True)[:27]),
        "20g",
        mn.read_broadcast_nav,
    ),
}

NASTY = [b"1e308", b"-1e308", b"1e29", b"NaN", b"inf", b"-1", b"0", b"99999999999999999999"]

mutation = st.one_of(
    st.tuples(st.just("flip"), st.integers(0, 10**6), st.integers(0, 255)),
    st.tuples(st.just("cut"), st.integers(0, 10**6), st.just(0)),
    st.tuples(st.just("number"), st.integers(0, 10**6), st.integers(0, len(NASTY) - 1)),
    st.tuples(st.just("garbage"), st.integers(0, 10**6), st.integers(0, 2**32 - 1)),
)


def _mutate(seed: bytes, mutations: list[tuple[str, int, int]]) -> bytes:
    b = bytearray(seed)
    for kind, at, value in mutations:
        if kind == "flip" and b:
            b[at % len(b)] = value
        elif kind == "cut":
            del b[at % (len(b) + 1) :]
        elif kind == "number":
            # Replace the digit run that holds byte `at` (or the next one).
            digits = [i for i, c in enumerate(b) if chr(c).isdigit()]
            if digits:
                i = digits[at % len(digits)]
                s, e = i, i
                while s > 0 and chr(b[s - 1]) in "0123456789.+-eED":
                    s -= 1
                while e < len(b) and chr(b[e]) in "0123456789.+-eED":
                    e += 1
                b[s:e] = NASTY[value].rjust(e - s)
        else:
            k = at % (len(b) + 1)
            b[k:k] = value.to_bytes(4, "little") * (1 + at % 7)
    return bytes(b)


def _read(name: str, content: bytes) -> str | None:
    """Reads ``content`` with reader ``name``: a result (None) or a
    ValueError naming the file (its message), in bounded time."""
    _, ext, reader = READERS[name]
    message = None
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"fuzzed.{ext}"
        path.write_bytes(content)
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # cut lines and implausible units warn
            try:
                reader(path)
            except ValueError as e:
                message = str(e)
        assert time.perf_counter() - start < 10.0
    assert message is None or "fuzzed." in message, message
    return message


@pytest.mark.parametrize("name", sorted(READERS))
@FUZZ
@given(mutations=st.lists(mutation, min_size=1, max_size=4))
def test_mutated_files_give_a_result_or_an_error_naming_the_file(name, mutations):
    _read(name, _mutate(READERS[name][0], mutations))


@pytest.mark.parametrize("name", sorted(READERS))
@FUZZ
@given(prefix=st.integers(0, 10**6), tail=st.binary(max_size=400))
def test_garbage_after_a_valid_beginning(name, prefix, tail):
    seed = READERS[name][0]
    _read(name, seed[: prefix % (len(seed) + 1)] + tail)


#: Columns of the satellite name in a record line of the formats with one
#: record per satellite and epoch.
LABEL = {"sp3": slice(1, 4), "rinex_obs": slice(0, 3)}


def _epoch_records(name: str, lines: list[bytes]) -> list[list[int]]:
    """Indices of the satellite record lines of each epoch of a seed of
    ``name`` (SP3: ``P`` lines after a ``*`` line; RINEX observations: the
    lines a ``>`` line announces)."""
    epochs: list[list[int]] = []
    if name == "sp3":
        for k, line in enumerate(lines):
            if line.startswith(b"*"):
                epochs.append([])
            elif line.startswith(b"P") and epochs:
                epochs[-1].append(k)
        return epochs
    k = next(i for i, line in enumerate(lines) if b"END OF HEADER" in line) + 1
    while k < len(lines):
        count = int(lines[k][32:35])
        epochs.append(list(range(k + 1, k + 1 + count)))
        k += 1 + count
    return epochs


def _repeat_a_satellite(name: str, kind: str, at: tuple[int, int, int]) -> tuple[bytes, str]:
    """The seed of ``name`` with one satellite's record of one epoch copied
    to another place in the epoch (``kind`` "duplicate"; a RINEX epoch's
    count goes up by one, so the copy is read as a record) or another
    record of the epoch relabelled with its name ("relabel"), and that name."""
    lines = READERS[name][0].splitlines(keepends=True)
    epochs = _epoch_records(name, lines)
    epoch, record, other = at
    records = epochs[epoch % len(epochs)]
    source = records[record % len(records)]
    label = lines[source][LABEL[name]]
    if kind == "duplicate":
        lines.insert(records[0] + other % (len(records) + 1), lines[source])
        if name == "rinex_obs":
            head = lines[records[0] - 1]
            lines[records[0] - 1] = head[:32] + b"%3d" % (len(records) + 1) + head[35:]
    else:
        target = records[(records.index(source) + 1 + other % (len(records) - 1)) % len(records)]
        line = lines[target]
        lines[target] = line[: LABEL[name].start] + label + line[LABEL[name].stop :]
    return b"".join(lines), label.decode().replace(" ", "0")


@pytest.mark.parametrize("name", sorted(LABEL))
@FUZZ
@given(
    kind=st.sampled_from(["duplicate", "relabel"]),
    at=st.tuples(st.integers(0, 10**6), st.integers(0, 10**6), st.integers(0, 10**6)),
)
def test_a_satellite_twice_in_an_epoch_is_refused(name, kind, at):
    # The second record silently replaced the first (a relabelled
    # line gave one satellite another's values and the other none).
    content, label = _repeat_a_satellite(name, kind, at)
    message = _read(name, content)
    assert message is not None and f"{label} has a second" in message, message


@pytest.mark.parametrize("name", sorted(READERS))
def test_the_seeds_read(name):
    seed, ext, reader = READERS[name]
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"seed.{ext}"
        path.write_bytes(seed)
        assert reader(path) is not None


def _ubx_frames(log: bytes) -> list[tuple[int, int, bytes]]:
    """The (class, id, payload) of each whole frame of a UBX log."""
    frames, at = [], 0
    while at + 8 <= len(log):
        length = int.from_bytes(log[at + 4 : at + 6], "little")
        if at + 8 + length > len(log):
            break
        frames.append((log[at + 2], log[at + 3], log[at + 6 : at + 6 + length]))
        at += 8 + length
    return frames


def _ubx_frame(cls: int, msg_id: int, payload: bytes) -> bytes:
    """A UBX frame with its Fletcher checksum (interface description §3.4)."""
    body = bytes([cls, msg_id]) + len(payload).to_bytes(2, "little") + payload
    a = b = 0
    for x in body:
        a = (a + x) & 0xFF
        b = (b + a) & 0xFF
    return b"\xb5\x62" + body + bytes([a, b])


#: Little-endian values no receiver reports, written into UBX payloads.
UBX_NASTY = [struct.pack("<d", v) for v in (math.inf, -math.inf, math.nan, 1e300, -1.0)] + [
    struct.pack("<f", math.inf),
    struct.pack("<i", -(2**31)),
    struct.pack("<H", 9999),
]

ubx_mutation = st.one_of(
    st.tuples(st.just("byte"), st.integers(0, 10**6), st.integers(0, 10**4), st.integers(0, 255)),
    st.tuples(
        st.just("field"), st.integers(0, 10**6), st.integers(0, 10**4),
        st.integers(0, len(UBX_NASTY) - 1),
    ),
    st.tuples(st.just("duplicate"), st.integers(0, 10**6), st.just(0), st.just(0)),
    st.tuples(st.just("delete"), st.integers(0, 10**6), st.just(0), st.just(0)),
)  # fmt: skip


@FUZZ
@given(mutations=st.lists(ubx_mutation, min_size=1, max_size=5))
def test_ubx_fields_behind_valid_checksums(tmp_path_factory, mutations):
    """Payload bytes and fields of the log's frames changed (±inf, NaN,
    1e300 measurements, a week of 9999, −2³¹ mm/s), every frame re-framed
    with its Fletcher checksum so the decoders see it: the log reads with
    only finite measurements and fixes, or is a ValueError naming the
    file; what ``convert`` writes of it memsnav reads back, or ``convert``
    says why it writes nothing."""
    from memsnav.realdata.convert import convert_ubx

    frames = _ubx_frames(READERS["ubx"][0])
    for kind, nth, at, value in mutations:
        k = nth % len(frames)
        cls, msg_id, payload = frames[k]
        if kind == "byte" and payload:
            p = bytearray(payload)
            p[at % len(p)] = value
            frames[k] = (cls, msg_id, bytes(p))
        elif kind == "field" and len(payload) >= len(UBX_NASTY[value]):
            new = UBX_NASTY[value]
            i = at % (len(payload) - len(new) + 1)
            frames[k] = (cls, msg_id, payload[:i] + new + payload[i + len(new) :])
        elif kind == "duplicate":
            frames.insert(k, frames[k])
        elif kind == "delete" and len(frames) > 1:
            del frames[k]
    folder = tmp_path_factory.mktemp("ubx")
    path = folder / "fuzzed.ubx"
    path.write_bytes(b"".join(_ubx_frame(*f) for f in frames))
    try:
        log, files = convert_ubx(path, folder / "rinex")
    except ValueError as e:
        assert "fuzzed." in str(e) or "no observations to write" in str(e), str(e)
        return
    for name in ("pseudorange", "carrier_phase", "doppler", "cn0"):
        assert np.isfinite(log.rawx[name]).all(), name
    for name in ("lla", "velocity_ned"):
        assert np.isfinite(getattr(log.fixes, name)).all(), name
    assert len(mn.read_rinex_obs(files["observations"]).time) <= len(log.rawx["epoch_gps_time"])
    assert mn.read_broadcast_nav(files["navigation"]).skipped == {}


REGRESSIONS = [p for p in sorted((DATA / "regressions").iterdir()) if p.suffix != ".md"]


@pytest.mark.parametrize("path", REGRESSIONS, ids=[p.name for p in REGRESSIONS])
def test_regression_files_are_refused_with_their_name(path):
    reader = {
        ".csv": mn.read_imu_csv,
        ".tag": mn.read_time_tag,
        ".pos": mn.read_pos,
        ".obs": mn.read_rinex_obs,
        ".nav": mn.Constellation.from_rinex_nav,
        ".sp3": mn.read_sp3,
    }[path.suffix]
    with pytest.raises(mn.ParseError, match=path.name):
        reader(path)


@FUZZ
@given(
    n=st.integers(1, 6),
    start=st.floats(0.0, 2e9),
    steps=st.lists(st.floats(0.001, 1e5), min_size=6, max_size=6),
    lat=st.floats(-90.0, 90.0),
    lon=st.floats(-180.0, 180.0),
    height=st.floats(-1e4, 1e7),
    std=st.floats(0.0, 1e6),
    speed=st.floats(-1e4, 1e4),
)
def test_what_write_pos_accepts_read_pos_reads_back(n, start, steps, lat, lon, height, std, speed):
    t = start + np.cumsum(steps[:n])
    lla = np.tile([np.radians(lat), np.radians(lon), height], (n, 1))
    s = np.full((n, 3), std)
    v = np.full((n, 3), speed)
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "x.pos"
        try:
            mn.realdata.readers.write_pos(path, t, lla, s, v, s)
        except ValueError as e:
            # Two epochs within the same millisecond cannot be told apart.
            assert "gps_time" in str(e) or "lla" in str(e), e
            return
        try:
            back = mn.read_pos(path)
        except ValueError as e:
            # Times within 0.5 ms of each other round to the same ms.
            assert "must increase" in str(e) and np.min(np.diff(t)) < 0.001, e
            return
    np.testing.assert_allclose(back.gps_time, np.round(t * 1000) / 1000, atol=1e-6)
    np.testing.assert_allclose(np.degrees(back.lla[:, :2]), [[lat, lon]] * n, atol=1e-9)
    np.testing.assert_allclose(back.lla[:, 2], height, atol=1e-4 + 1e-12 * abs(height))
    np.testing.assert_allclose(back.std_ned, s, atol=1e-4 + 1e-12 * std)
    np.testing.assert_allclose(back.velocity_ned, v, atol=1e-5)
