"""RINEX reading on the GEONET data (GSI GEONET, redistributed in RTKLIB's test data), plus clear errors on
bad files. (Single-point positioning of the same files: tests/test_gnss_ephemeris.py.)"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.errors import RecordsSkippedWarning, RinexError
from gnssatt.rinex import read_nav, read_obs

DATA = geonet_dir()  # the GEONET pair shipped in the package (gnssatt/data)
needs_data = pytest.mark.skipif(not DATA.is_dir(), reason="GEONET test data not present")


@needs_data
def test_geonet_obs_header_and_first_epoch() -> None:
    obs = read_obs(DATA / "07590920.05o")
    assert obs.version == pytest.approx(2.10)
    assert obs.marker_name == "0759"
    np.testing.assert_allclose(obs.approx_position_m, [-3976219.5082, 3382372.5671, 3652512.9849])
    assert obs.codes == ("L1", "C1", "L2", "P2")
    assert obs.data.shape == (120, 11, 4)
    assert str(obs.time[0]) == "2005-04-02T00:00:00.000000000"
    assert str(obs.time[-1]) == "2005-04-02T00:59:30.005000000"
    g03 = obs.sats.index("G03")
    np.testing.assert_allclose(obs.data[0, g03], [55923622.160, 24767686.375, 43647388.242, 24767684.822])
    assert obs.lli[0, g03, 2] == 4  # "43647388.2424": LLI 4 (anti-spoofing) on L2
    assert obs.code_for("G", "C", 1) == "C1" and obs.code_for("G", "C", 2) == "P2"
    assert np.isnan(obs.data[0, obs.sats.index("G01")]).all()  # G01 rises later


@needs_data
def test_geonet_nav_records() -> None:
    nav = read_nav(DATA / "07590920.05n")
    k = nav.kepler
    first = int(np.flatnonzero(k.sats == "G01")[0])
    assert k.fields["sqrt_a"][first] == pytest.approx(5153.63647842)
    # toe 525600 s of week 1316 = 2005-04-02 02:00 GPST (the record's toc)
    assert k.toe_ns[first] == k.toc_ns[first]
    np.testing.assert_allclose(nav.iono_alpha, [1.1180e-08, 1.4900e-08, -5.9600e-08, -5.9600e-08])


def _write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


@needs_data
def test_truncated_obs_names_file_and_line(tmp_path: Path) -> None:
    lines = (DATA / "07590920.05o").read_text().splitlines()
    bad = _write(tmp_path, "trunc.05o", "\n".join(lines[:22]) + "\n")
    # the epoch of line 18 announces 8 satellites the file does not hold: left out with a warning, and
    # the header alone is a file of zero epochs
    with pytest.warns(
        RecordsSkippedWarning, match=r"trunc\.05o: 1 epoch left out.*the epoch at line 18 announces 8 sat"
    ):
        obs = read_obs(bad)
    assert len(obs.time) == 0 and obs.data.shape == (0, 0, len(obs.codes))


@needs_data
def test_unknown_version_and_missing_header_lines(tmp_path: Path) -> None:
    text = (DATA / "07590920.05o").read_text()
    bad = _write(
        tmp_path,
        "v9.05o",
        text.replace("     2.10           OBSERVATION", "     9.10           OBSERVATION", 1),
    )
    with pytest.raises(RinexError, match=r"v9\.05o, line 1: unknown RINEX version 9\.1"):
        read_obs(bad)
    no_types = "".join(ln for ln in text.splitlines(keepends=True) if "TYPES OF OBSERV" not in ln)
    with pytest.raises(RinexError, match=r"missing header line '# / TYPES OF OBSERV'"):
        read_obs(_write(tmp_path, "notypes.05o", no_types))
    no_end = "".join(text.splitlines(keepends=True)[:10])
    with pytest.raises(RinexError, match=r"missing header line 'END OF HEADER'"):
        read_obs(_write(tmp_path, "noend.05o", no_end))
    garbled = text.replace("  55923622.160  ", "  5592x622.160  ", 1)
    with pytest.raises(RinexError, match=r"garbled\.05o, line 19: expected a number"):
        read_obs(_write(tmp_path, "garbled.05o", garbled))
    with pytest.raises(RinexError, match="cannot open"):
        read_obs(tmp_path / "absent.05o")
    with pytest.raises(RinexError, match="expected an observation file"):
        read_obs(DATA / "07590920.05n")


@needs_data
def test_truncated_nav(tmp_path: Path) -> None:
    lines = (DATA / "07590920.05n").read_text().splitlines()
    bad = _write(tmp_path, "trunc.05n", "\n".join(lines[:16]) + "\n")
    with pytest.warns(RecordsSkippedWarning, match=r"trunc\.05n: 1 record left out.*G01 at line 13"):
        nav = read_nav(bad)
    assert len(nav.kepler) == 0


def test_rinex_error_pickles() -> None:
    import pickle

    err = pickle.loads(pickle.dumps(RinexError("a.05o", 7, "expected a number")))
    assert isinstance(err, RinexError) and err.line == 7 and str(err) == "a.05o, line 7: expected a number"


def test_path_of_the_wrong_kind_or_a_folder(tmp_path: Path) -> None:
    from gnssatt.errors import InvalidTypeError

    for reader in (read_obs, read_nav):
        for bad in (None, 3, b"file.05o"):
            with pytest.raises(InvalidTypeError, match=r"expected path as a str or os\.PathLike"):
                reader(bad)  # type: ignore[arg-type]
        with pytest.raises(RinexError, match="cannot open"):
            reader(tmp_path)


def test_dense_arrays_have_a_limit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from gnssatt.rinex import obs as obs_module
    from gnssatt.rinex.writer import write_obs

    path = tmp_path / "small.24o"
    t = np.datetime64("2024-01-01T00:00:00", "ns") + np.arange(3) * np.timedelta64(1, "s")
    write_obs(path, t, ["G01", "G02"], {"C1C": np.full((3, 2), 2.2e7), "L1C": np.full((3, 2), 1.1e8)})
    assert read_obs(path).data.shape == (3, 2, 2)
    monkeypatch.setattr(obs_module, "MAX_CELLS", 11)
    with pytest.raises(
        RinexError, match=r"3 epochs x 2 satellites x 2 codes = 12 values exceed the limit of 11"
    ):
        read_obs(path)
