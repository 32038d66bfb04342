"""Hatanaka-compressed and gzip RINEX files through the optional ``hatanaka`` package; a clear error
without it."""

from __future__ import annotations

import gzip
import sys
from pathlib import Path

import numpy as np
import pytest

from gnssatt.data import geonet_dir
from gnssatt.errors import RinexError
from gnssatt.rinex import read_nav, read_obs

DATA = geonet_dir()  # the GEONET pair shipped in the package (gnssatt/data)
needs_data = pytest.mark.skipif(not DATA.is_dir(), reason="GEONET test data not present")


@pytest.mark.slow
@needs_data
def test_hatanaka_and_gzip_read_as_plain(tmp_path: Path) -> None:
    hatanaka = pytest.importorskip("hatanaka")
    plain = read_obs(DATA / "07590920.05o")
    crx = tmp_path / "07590920.05d"
    crx.write_bytes(hatanaka.rnx2crx((DATA / "07590920.05o").read_bytes()))
    assert crx.read_bytes()[60:80].startswith(b"CRINEX VERS")
    packed = read_obs(crx)
    assert packed.codes == plain.codes and packed.sats == plain.sats
    np.testing.assert_array_equal(packed.time, plain.time)
    np.testing.assert_array_equal(packed.data, plain.data)
    gz = tmp_path / "07590920.05n.gz"
    gz.write_bytes(gzip.compress((DATA / "07590920.05n").read_bytes()))
    np.testing.assert_array_equal(read_nav(gz).kepler.toe_ns, read_nav(DATA / "07590920.05n").kepler.toe_ns)


@needs_data
def test_compressed_without_hatanaka_says_what_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    gz = tmp_path / "07590920.05o.gz"
    gz.write_bytes(gzip.compress((DATA / "07590920.05o").read_bytes()))
    monkeypatch.setitem(sys.modules, "hatanaka", None)  # import fails as if not installed
    with pytest.raises(RinexError, match=r"07590920\.05o\.gz: compressed .*pip install gnssatt\[hatanaka\]"):
        read_obs(gz)


def test_corrupt_compressed_file(tmp_path: Path) -> None:
    pytest.importorskip("hatanaka")
    bad = tmp_path / "bad.crx"
    bad.write_bytes(b"\x1f\x8b" + b"\x00" * 40)
    with pytest.raises(RinexError, match=r"bad\.crx: cannot decompress"):
        read_obs(bad)
