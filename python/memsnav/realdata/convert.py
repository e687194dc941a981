"""Raw receiver logs to RINEX (``memsnav convert``): a u-blox UBX log's
measurements (RXM-RAWX, every system and signal) as a RINEX 3.04
observation file and its decoded GPS LNAV and CNAV, Galileo I/NAV and
BeiDou D1 ephemerides (RXM-SFRBX) as a RINEX 4.00 navigation file (or
RINEX 3.04, which has no CNAV record). The decoding and the writing are in the Rust
core (``memsnav_core::logs::ubx``, ``memsnav_core::gnss::rinex_write``);
docs/how-to/convert-ublox.md, "Raw u-blox logs", describes what is kept."""

from __future__ import annotations

from pathlib import Path

from memsnav._memsnav import UbxLog, read_ubx

__all__ = ["convert_ubx"]


def convert_ubx(
    path: str | Path, output: str | Path, *, rinex_version: str | None = None
) -> tuple[UbxLog, dict[str, Path]]:
    """Reads the UBX log ``path`` and writes ``<output>/<stem>.obs`` and
    ``<output>/<stem>.nav`` (the folder made when missing, files of those
    names replaced); returns the log as read and the two paths by kind
    (``"observations"``, ``"navigation"``). ``rinex_version`` is the
    navigation file's: None for the default, RINEX 4.00 (GPS CNAV
    ephemerides included), or ``"3.04"`` (no CNAV record: they are left
    out); anything else is a ``ValueError`` naming ``rinex_version``."""
    path = Path(path)
    folder = Path(output)
    folder.mkdir(parents=True, exist_ok=True)
    log = read_ubx(path)
    files = {
        "observations": folder / f"{path.stem}.obs",
        "navigation": folder / f"{path.stem}.nav",
    }
    log.write_rinex_obs(files["observations"])
    log.write_rinex_nav(files["navigation"], rinex_version=rinex_version)
    return log, files
