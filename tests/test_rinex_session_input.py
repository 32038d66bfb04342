"""session_input / nav_input: common epochs and satellites, signal slots, GLONASS channels, time systems,
and the errors and warnings a user meets (each naming the file)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.errors import InvalidInputError, RinexError
from gnssatt.gnss.session_input import (
    NO_CHANNEL,
    EpochsDroppedWarning,
    SystemDroppedWarning,
    session_input,
)
from gnssatt.rinex import read_nav, read_obs, write_obs
from gnssatt.rinex.nav import gps_ns, nav_input
from gnssatt.rinex.obs import RinexObs

T0 = np.datetime64("2024-03-01T10:00:00", "ns")
DATA = Path(__file__).parent / "data"


def _geonet() -> list[RinexObs]:
    d = geonet_dir()
    return [read_obs(d / "07590920.05o"), read_obs(d / "30400920.05o")]


def _write(path: Path, sats: list[str], codes: list[str], n_ep: int = 4, **kw: object) -> RinexObs:
    rows = np.arange(n_ep)[:, None] * 10.0 + np.arange(len(sats))[None, :]
    obs = {c: 2.0e7 + 1e3 * k + rows for k, c in enumerate(codes)}
    t = kw.pop("time", T0 + np.arange(n_ep) * np.timedelta64(1, "s"))
    write_obs(path, t, sats, obs, approx_position_m=kw.pop("pos", (1.0, 2.0, 3.0)), **kw)  # type: ignore[arg-type]
    return read_obs(path)


def test_geonet_pair_l1_l2() -> None:
    base, rover = _geonet()
    si = session_input([base, rover], frequencies=2)
    assert si.time_gpst_ns.shape == (120,) and si.epochs_dropped == (0, 0)
    seen = [{s for k, s in enumerate(o.sats) if np.isfinite(o.get("L1")[:, k]).any()} for o in (base, rover)]
    assert si.sats == tuple(sorted(seen[0] & seen[1])) and len(si.sats) == 11
    assert si.code_m.shape == (2, 120, 11, 3) and si.code_m.flags.c_contiguous
    assert si.signal_codes[base.path] == {"G": ("C1/L1", "P2/L2", "")}
    np.testing.assert_array_equal(si.time_gpst_ns, gps_ns(base.time))
    # values are the file's, at the right epoch and satellite; the rover's moved from its own labels (up to
    # 9 ms off) onto the base's: code - c delta, phase - f delta
    k, j = rover.sats.index("G19"), si.sats.index("G19")
    delta_s = (gps_ns(rover.time) - gps_ns(base.time)) * 1e-9
    assert np.abs(delta_s).max() > 1e-3
    np.testing.assert_allclose(
        si.phase_cycles[1, :, j, 1], rover.get("L2")[:, k] - 1227.60e6 * delta_s, rtol=0, atol=1e-6
    )
    np.testing.assert_allclose(
        si.code_m[1, :, j, 0], rover.get("C1")[:, k] - 299_792_458.0 * delta_s, rtol=0, atol=1e-6
    )
    np.testing.assert_array_equal(si.code_m[0, :, j, 0], base.get("C1")[:, base.sats.index("G19")])
    assert np.isnan(si.phase_cycles[..., 2]).all() and np.isnan(si.doppler_hz).all()
    np.testing.assert_array_equal(si.approx_position_m[0], base.approx_position_m)
    assert (si.glonass_channel == NO_CHANNEL).all()
    one = session_input([base, rover], frequencies=1)
    assert np.isnan(one.phase_cycles[..., 1:]).all()
    np.testing.assert_array_equal(one.phase_cycles[..., 0], si.phase_cycles[..., 0])


def test_missing_epochs_are_counted_and_their_slips_carried(tmp_path: Path) -> None:
    sats = ["G01", "G02"]
    base = _write(tmp_path / "a.rnx", sats, ["C1C", "L1C"], n_ep=6)
    t = T0 + np.arange(6) * np.timedelta64(1, "s")
    lli = {"L1C": np.zeros((6, 2))}
    lli["L1C"][2, 1] = 1  # a slip at an epoch the base lacks below
    rover = _write(tmp_path / "b.rnx", sats, ["C1C", "L1C"], n_ep=6, time=t, lli=lli)
    base_cut = _write(tmp_path / "c.rnx", sats, ["C1C", "L1C"], n_ep=5, time=t[[0, 1, 3, 4, 5]])
    with pytest.warns(EpochsDroppedWarning, match=f"left out: {rover.path}: 1 of 6$"):
        si = session_input([base_cut, rover])
    assert si.epochs_dropped == (0, 1) and len(si.time_gpst_ns) == 5
    assert si.lli[1, :, 1, 0].tolist() == [0, 0, 1, 0, 0]  # moved to the next common epoch
    si = session_input([base, rover])
    assert si.lli[1, :, 1, 0].tolist() == [0, 0, 1, 0, 0, 0]


def test_labels_matched_within_tolerance(tmp_path: Path) -> None:
    t = T0 + np.arange(4) * np.timedelta64(1, "s")
    a = _write(tmp_path / "a.rnx", ["G01"], ["C1C", "L1C"], time=t)
    b = _write(tmp_path / "b.rnx", ["G01"], ["C1C", "L1C"], time=t + np.timedelta64(9, "ms"))
    c = _write(tmp_path / "c.rnx", ["G01"], ["C1C", "L1C"], time=t + np.timedelta64(30, "ms"))
    assert session_input([a, b]).epochs_dropped == (0, 0)
    with pytest.raises(RinexError, match="no epoch common") as err:
        session_input([a, c])
    assert a.path in str(err.value) and c.path in str(err.value)
    # 100 Hz: labels 5 ms apart are not one epoch (the tolerance drops below half the 10 ms spacing)
    fast = T0 + np.arange(4) * np.timedelta64(10, "ms")
    d = _write(tmp_path / "d.rnx", ["G01"], ["C1C", "L1C"], time=fast)
    e = _write(tmp_path / "e.rnx", ["G01"], ["C1C", "L1C"], time=fast + np.timedelta64(4, "ms"))
    f = _write(tmp_path / "f.rnx", ["G01"], ["C1C", "L1C"], time=fast + np.timedelta64(5, "ms"))
    assert session_input([d, e]).epochs_dropped == (0, 0)
    with pytest.raises(RinexError, match="labels within 4999999 ns"):
        session_input([d, f])


def test_file_without_phase_is_named(tmp_path: Path) -> None:
    a = _write(tmp_path / "a.rnx", ["G01"], ["C1C", "L1C"])
    b = _write(tmp_path / "b.rnx", ["G01"], ["C1C", "D1C"])
    with pytest.raises(RinexError, match="expected carrier-phase observations") as err:
        session_input([a, b])
    assert err.value.path == b.path


def test_system_lacking_in_one_file_is_dropped_with_a_warning(tmp_path: Path) -> None:
    a = _write(tmp_path / "a.rnx", ["G01", "E01"], ["C1C", "L1C"])
    b = _write(tmp_path / "b.rnx", ["G01"], ["C1C", "L1C"])
    with pytest.warns(SystemDroppedWarning, match=f"system E dropped: no carrier phase of it in {b.path}"):
        si = session_input([a, b])
    assert si.sats == ("G01",) and set(si.signal_codes[a.path]) == {"G"}
    with pytest.raises(RinexError, match="expected carrier-phase observations") as err:
        session_input([a, b], systems="E")
    assert err.value.path == b.path
    e_only = _write(tmp_path / "e.rnx", ["E01"], ["C1C", "L1C"])
    with pytest.raises(RinexError, match="found none common") as err, warnings.catch_warnings():
        warnings.simplefilter("ignore", SystemDroppedWarning)
        session_input([e_only, b])
    assert err.value.path == f"{e_only.path}, {b.path}"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        session_input([b, b])  # systems no file has: dropped silently with the default


def test_sats_in_system_order_and_glonass_channels(tmp_path: Path) -> None:
    sats = ["J02", "C06", "R05", "G10", "E11", "R01"]
    codes = ["C1C", "L1C", "C2I", "L2I"]
    a = _write(tmp_path / "a.rnx", sats, codes, glonass_channels={"R05": -3})
    b = _write(tmp_path / "b.rnx", sats, codes)
    si = session_input([b, a])
    assert si.sats == ("G10", "R01", "R05", "E11", "C06", "J02")
    assert si.glonass_channel.tolist() == [99, 99, -3, 99, 99, 99]  # R01: no header, no nav
    nav = read_nav(DATA / "BRDM00DLR_R_20130010000_01D_MN.rnx")
    ch = dict(zip(nav.glonass.sats.tolist(), nav.glonass.channel.tolist(), strict=True))
    si = session_input([b, a], nav=nav)
    assert si.glonass_channel[1] == ch["R01"] and si.glonass_channel[2] == -3  # the header wins


def test_time_systems_to_gpst(tmp_path: Path) -> None:
    a = _write(tmp_path / "a.rnx", ["C06"], ["C2I", "L2I"])
    label = "         TIME OF FIRST OBS"
    text = (tmp_path / "a.rnx").read_text().replace(f"     GPS{label}", f"     BDT{label}")
    (tmp_path / "b.rnx").write_text(text)
    b = read_obs(tmp_path / "b.rnx")
    assert b.time_system == "BDT"
    si = session_input([b, b])
    np.testing.assert_array_equal(si.time_gpst_ns, gps_ns(a.time) + 14_000_000_000)  # BDT = GPST - 14 s


def test_glonass_time_labels_with_leap_seconds(tmp_path: Path) -> None:
    t = T0 + np.arange(4) * np.timedelta64(1, "s")
    gps = _write(tmp_path / "a.rnx", ["R01"], ["C1C", "L1C"], time=t)
    # the same instants labelled in GLONASS time, UTC(SU) + 3 h = GPST - 18 s + 3 h in 2024
    _write(tmp_path / "b.rnx", ["R01"], ["C1C", "L1C"], time=t + np.timedelta64(3 * 3600 - 18, "s"))
    label = "         TIME OF FIRST OBS"
    text = (tmp_path / "b.rnx").read_text().replace(f"     GPS{label}", f"     GLO{label}")
    for leaps, shift in (("    18", 0), ("    17", 1)):
        end = f"{'':60}END OF HEADER"
        with_leaps = text.replace(end, f"{leaps:<60}LEAP SECONDS\n{end}")
        (tmp_path / "c.rnx").write_text(with_leaps)
        glo = read_obs(tmp_path / "c.rnx")
        assert glo.time_system == "GLO" and glo.leap_seconds == int(leaps)
        si = session_input([glo, glo])
        np.testing.assert_array_equal(si.time_gpst_ns, gps_ns(gps.time) - shift * 1_000_000_000)
    (tmp_path / "d.rnx").write_text(text)  # no LEAP SECONDS: the table (18 s since 2017)
    np.testing.assert_array_equal(
        session_input([read_obs(tmp_path / "d.rnx")] * 2).time_gpst_ns, gps_ns(gps.time)
    )


def test_bad_arguments() -> None:
    obs = _geonet()
    for kw in ({"systems": "GX"}, {"systems": ""}, {"systems": "GG"}, {"frequencies": 0}, {"frequencies": 4}):
        with pytest.raises(InvalidInputError):
            session_input(obs, **kw)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="2 to 16 receivers"):
        session_input(obs[:1])


def test_nav_input_fields_per_system() -> None:
    nav = read_nav(DATA / "CBW100NLD_R_20210010000_01D_MN.rnx")
    ni = nav_input(nav)
    k = ni.kepler
    n = len(nav.kepler)
    assert k["af"].shape == (n, 3) and k["tgd_s"].shape == (n, 2) and k["toe_gpst_ns"].dtype == np.int64
    f = nav.kepler.fields
    sysl = np.array([s[0] for s in k["sat"]])
    for s in "GEC":
        assert (sysl == s).any()
    np.testing.assert_array_equal(k["tgd_s"][sysl == "C", 1], f["iodc_tgd2"][sysl == "C"])  # TGD2
    np.testing.assert_array_equal(k["tgd_s"][sysl == "E", 1], f["iodc_tgd2"][sysl == "E"])  # BGD E5b/E1
    assert np.isnan(k["tgd_s"][sysl == "G", 1]).all()
    assert np.isfinite(k["data_source"][sysl == "E"]).all() and np.isnan(k["data_source"][sysl != "E"]).all()
    # BeiDou times in GPST: toc label (BDT) + 14 s
    c = np.flatnonzero(sysl == "C")[0]
    assert (k["toc_gpst_ns"][c] - nav.kepler.toc_ns[c]) == 0  # the reader already converted
    brdm = nav_input(read_nav(DATA / "BRDM00DLR_R_20130010000_01D_MN.rnx"))
    g = brdm.glonass
    assert g["position_m"].shape == (len(g["sat"]), 3) and g["channel"].dtype == np.int64
    qzss = brdm.kepler["sat"].astype(str)
    assert any(s.startswith("J") for s in qzss)  # QZSS kept whatever its health word


def test_nav_input_klobuchar_and_leap_seconds() -> None:
    d = geonet_dir()
    ni = nav_input(read_nav(d / "07590920.05n"))
    assert ni.klobuchar is not None and ni.klobuchar.shape == (8,)
    text = (d / "07590920.05n").read_text()
    assert float(text.split("ION ALPHA")[0].splitlines()[-1][2:14].replace("D", "E")) == ni.klobuchar[0]


def _rinex4(v3_text: str) -> str:
    """A RINEX 3 mixed navigation text in RINEX 4 layout: record markers, the header's GPS Klobuchar moved
    into an ``ION`` record, and records the reader skips (a CNAV ephemeris, an STO record)."""
    lines = v3_text.replace("\r", "").splitlines()
    end = next(k for k, x in enumerate(lines) if "END OF HEADER" in x)
    header = [x for x in lines[: end + 1] if x[60:].strip() not in ("IONOSPHERIC CORR", "TIME SYSTEM CORR")]
    header[0] = f"{'4.00':>9}" + header[0][9:]
    corr = {x[:4]: x[5:53] for x in lines[:end] if x[60:].strip() == "IONOSPHERIC CORR"}
    a = [float(corr["GPSA"][12 * k : 12 * k + 12]) for k in range(4)]
    b = [float(corr["GPSB"][12 * k : 12 * k + 12]) for k in range(4)]

    def d19(*v: float) -> str:
        return "".join(f"{x:19.12e}" for x in v)

    body = [
        "> ION G19 LNAV",
        "    2021 01 01 00 00 00" + d19(*a[:3]),
        "    " + d19(a[3], *b[:3]),
        "    " + d19(b[3], 1.0),
        "> STO G19 LNAV",
        "    2021 01 01 00 00 00 GPUT      UTC(USNO)",
        "    " + d19(0.0, 0.0, 0.0, 0.0),
        "> EPH G20 CNAV",
        *["    " + d19(0.0, 0.0, 0.0, 0.0)] * 9,
    ]
    message = {"G": "LNAV", "E": "INAV", "C": "D1"}
    for x in lines[end + 1 :]:
        if x[:1].isalpha():
            msg = "D2" if x[:3] == "C05" else message[x[0]]
            body.append(f"> EPH {x[:3]} {msg}")
        body.append(x)
    return "\n".join(header + body) + "\n"


def test_rinex4_navigation_reads_as_rinex3(tmp_path: Path) -> None:
    v3 = read_nav(DATA / "CBW100NLD_R_20210010000_01D_MN.rnx")
    p = tmp_path / "v4.rnx"
    p.write_text(_rinex4((DATA / "CBW100NLD_R_20210010000_01D_MN.rnx").read_text()))
    v4 = read_nav(p)
    assert v4.skipped == {"STO G LNAV": 1, "EPH G CNAV": 1}
    np.testing.assert_array_equal(v4.kepler.sats, v3.kepler.sats)
    for name, values in v3.kepler.fields.items():
        np.testing.assert_array_equal(v4.kepler.fields[name], values, err_msg=name)
    np.testing.assert_array_equal(v4.kepler.toe_ns, v3.kepler.toe_ns)
    np.testing.assert_array_equal(v4.iono_alpha, v3.iono_alpha)
    np.testing.assert_array_equal(v4.iono_beta, v3.iono_beta)
    assert v4.leap_seconds == v3.leap_seconds == 18
    bad = p.read_text().replace("> EPH E01 INAV\n", "")
    p.write_text(bad)
    with pytest.raises(RinexError, match="expected a record marker"):
        read_nav(p)
